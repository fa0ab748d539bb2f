// FrameAnalyzer's registration passes: the registration from its seed, the
// propeller mask's passes, the window-bias correction and the direct stereo
// fit, each refining the pose the one before left.

#include "aar/analyzer/frame_analysis.h"
// Eigen before OpenCV's Eigen utility header.
#include <algorithm>
#include <opencv2/core/eigen.hpp>

#include "aar/analyzer/window_bias.h"

namespace aar {
namespace {

// Near plane of the model's z-buffer (window bias): the receiver is metres away [m].
constexpr double kModelNearM = 0.1;

}  // namespace

RegistrationResult FrameAnalyzer::Register(const std::vector<Eigen::Vector3d>& sensed,
                                           const std::optional<Pose>& previous) const {
  return RegisterFrom(sensed, options_.seed == IcpSeed::kPreviousFrame && previous
                                  ? IsometryFromPose(*previous)
                                  : InitialGuessAtCentroid(sensed, model_points_));
}

RegistrationResult FrameAnalyzer::RegisterFrom(const std::vector<Eigen::Vector3d>& sensed,
                                               const Eigen::Isometry3d& initial) const {
  return registration_->Register(sensed, initial);
}

void FrameAnalyzer::MaskPropellersAndRegister(const std::vector<Eigen::Vector3d>& sensed,
                                              RegistrationResult& icp) const {
  if (!options_.mask_propellers) return;
  const PropellerMaskOptions& m = options_.propeller_mask;
  for (int pass = 0; pass < m.passes; ++pass) {
    const double axial_half_width_m = pass == 0 ? m.first_axial_half_width_m : m.axial_half_width_m;
    const RegistrationResult masked =
        RegisterFrom(OutsidePropellerDiscs(sensed, icp.tanker_from_receiver, tanker_from_rect_left_.translation(), m,
                                           axial_half_width_m),
                     icp.tanker_from_receiver);
    // A registration that moves the discs out of the mask that made it is not trusted: keep the last pose.
    if (!PropellerMaskAgrees(icp.tanker_from_receiver, masked.tanker_from_receiver, axial_half_width_m)) break;
    icp = masked;
  }
}

bool FrameAnalyzer::CorrectWindowBias(const cv::Mat& rect_left, const cv::Mat& rect_right, const cv::Rect& region,
                                      SensedCloud& cloud, RegistrationResult& icp) const {
  // The window's bias predicted from the model at the registered pose
  // (window_bias.h), subtracted, and the cloud registered again from there.
  WindowBiasOptions window_bias = options_.window_bias;
  window_bias.half_window_px = options_.subpixel.half_window_px;
  window_bias.slanted = options_.subpixel.slanted;
  const cv::Mat model_disparity = ModelDisparity(
      *receiver_mesh_, calibration_, tanker_from_rect_left_.inverse() * icp.tanker_from_receiver, region, kModelNearM);
  const std::vector<double> bias =
      PredictWindowBias(rect_left, rect_right, model_disparity, region.tl(), cloud.pixels, window_bias);
  cv::Mat q64;
  calibration_.Q.convertTo(q64, CV_64F);
  Eigen::Matrix4d q;
  cv::cv2eigen(q64, q);
  SensedCloud corrected_cloud = cloud;
  double largest_move_m = 0.0;  // of a sensed point by its correction
  for (size_t k = 0; k < bias.size(); ++k) {
    Eigen::Vector3d& pixel = corrected_cloud.pixels[k];
    pixel.z() -= bias[k];
    const Eigen::Vector4d h = q * Eigen::Vector4d(pixel.x(), pixel.y(), pixel.z(), 1.0);
    const Eigen::Vector3d corrected = tanker_from_rect_left_ * Eigen::Vector3d(h.head<3>() / h.w());
    largest_move_m = std::max(largest_move_m, (corrected - cloud.points_in_tanker[k]).norm());
    corrected_cloud.points_in_tanker[k] = corrected;
  }
  RegistrationResult corrected = RegisterFrom(corrected_cloud.points_in_tanker, icp.tanker_from_receiver);
  MaskPropellersAndRegister(corrected_cloud.points_in_tanker, corrected);
  // Corrections of at most largest_move_m cannot move the receiver by more
  // than about that much: a registration that jumps further has slid into
  // another minimum (a far receiver's few points), and the first one stands
  // with its cloud.
  double model_move_m = 0.0;
  const Eigen::Isometry3d change = corrected.tanker_from_receiver * icp.tanker_from_receiver.inverse();
  for (const Eigen::Vector3d& m : model_points_) {
    const Eigen::Vector3d at = icp.tanker_from_receiver * m;
    model_move_m = std::max(model_move_m, (change * at - at).norm());
  }
  if (!(model_move_m <= 2.0 * largest_move_m)) return false;
  icp = corrected;
  cloud = std::move(corrected_cloud);
  return true;
}

void FrameAnalyzer::RefineDirectly(const cv::Mat& rect_left, const cv::Mat& rect_right, const cv::Rect& region,
                                   RegistrationResult& icp) const {
  const DirectStereoResult direct =
      RefineDirectStereo(*receiver_mesh_, calibration_, rect_left, rect_right, region,
                         tanker_from_rect_left_.inverse() * icp.tanker_from_receiver, options_.direct);
  if (direct.pixels > 0) icp.tanker_from_receiver = tanker_from_rect_left_ * direct.rect_left_from_receiver;
}

}  // namespace aar
