#include "aar/analyzer/frame_analysis.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <opencv2/imgcodecs.hpp>

#include "aar/analyzer/dataset_image.h"
#include "aar/analyzer/subpixel.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/progress.h"
#include "aar/random_stream.h"
#include "aar/region.h"
#include "aar/text.h"

namespace aar {
namespace {

// Adds the measuring stages of an earlier attempt at the same frame (a lost
// tracking region, a failed seed) to the times of the one that counts.
void AddAttemptTimes(StageTimes& times, const StageTimes& attempt) {
  times.rectify_ms += attempt.rectify_ms;
  times.disparity_ms += attempt.disparity_ms;
  times.reproject_ms += attempt.reproject_ms;
  times.icp_ms += attempt.icp_ms;
}

// R1^T as a transform: rectified left camera to left camera.
Eigen::Isometry3d LeftFromRectLeft(const StereoCalibration& calibration) {
  cv::Mat r1;
  calibration.R1.convertTo(r1, CV_64F);
  Eigen::Isometry3d left_from_rect_left = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) left_from_rect_left.linear()(i, j) = r1.at<double>(j, i);
  }
  return left_from_rect_left;
}

// Reads one image of the pair, checking its hash against the sidecar and the manifest.
cv::Mat ReadImage(const OpenedDataset& dataset, const FileRef& ref, int flags = cv::IMREAD_COLOR) {
  return ReadListedImage(dataset, ref, flags, "image");
}

// The receiver's pose at `time_s` by constant velocity from the last two
// estimates (the last one alone when there is one); nullopt without one.
std::optional<Pose> PredictedPose(const TrackHistory& history, double time_s) {
  if (!history.last) return std::nullopt;
  Pose predicted = history.last->second;
  if (history.before_last && history.last->first > history.before_last->first) {
    const double k = (time_s - history.last->first) / (history.last->first - history.before_last->first);
    const Pose& a = history.before_last->second;
    const Pose& b = history.last->second;
    predicted.translation_m = b.translation_m + k * (b.translation_m - a.translation_m);
    predicted.roll_deg = b.roll_deg + k * WrapDegrees(b.roll_deg - a.roll_deg);
    predicted.pitch_deg = b.pitch_deg + k * WrapDegrees(b.pitch_deg - a.pitch_deg);
    predicted.yaw_deg = b.yaw_deg + k * WrapDegrees(b.yaw_deg - a.yaw_deg);
  }
  return predicted;
}

}  // namespace

FrameAnalyzer::FrameAnalyzer(const StereoCalibration& calibration, const Eigen::Isometry3d& tanker_from_left,
                             const ReferenceModel& model, const FrameAnalysisOptions& options,
                             const ReferenceModel* full_surface)
    : calibration_(calibration),
      tanker_from_left_(tanker_from_left),
      focal_times_baseline_px_m_(std::abs(calibration.Q.at<double>(2, 3) / calibration.Q.at<double>(3, 2))),
      tanker_from_rect_left_(tanker_from_left * LeftFromRectLeft(calibration)),
      rectifier_(calibration),
      model_points_(model.points_in_receiver),
      options_(options) {
  options_.Check();
  if (options_.registration == Registration::kPointToPoint) {
    registration_ = std::make_unique<IcpRegistration>(model.points_in_receiver, options_.icp);
  } else {
    StereoNoiseGeometry geometry;
    geometry.camera_centre_in_tanker = tanker_from_left.translation();
    geometry.optical_axis_in_tanker = tanker_from_left.linear().col(2);
    geometry.focal_px = std::abs(calibration.Q.at<double>(2, 3));
    geometry.focal_times_baseline_px_m = focal_times_baseline_px_m_;
    auto plane_icp = std::make_unique<PlaneIcpRegistration>(model.points_in_receiver, model.normals_in_receiver,
                                                            geometry, options_.plane_icp);
    if (options_.pair_sensed_with_full_surface && full_surface != nullptr) {
      plane_icp->SetSensedPairingSurface(full_surface->points_in_receiver, full_surface->normals_in_receiver);
    }
    registration_ = std::move(plane_icp);
  }
}

void FrameAnalyzer::SetReceiverMesh(TriangleMesh receiver) {
  receiver_mesh_ = std::make_unique<TriangleMesh>(std::move(receiver));
}

void FrameAnalyzer::EnableBoomMask(TriangleMesh boom, TriangleMesh tube) {
  if (!options_.mask_boom) return;
  boom_masker_ = std::make_unique<BoomMasker>(std::move(boom), std::move(tube), calibration_, tanker_from_rect_left_,
                                              options_.boom_mask);
}

int FrameAnalyzer::DisparitiesFor(double needed_px) const {
  // 10 % and 2 px of margin for the estimate's error, in StereoBM's steps of 16.
  const double wanted_px = needed_px * 1.1 + 2.0;
  if (!std::isfinite(wanted_px)) return options_.disparity.num_disparities;
  return std::max(16, static_cast<int>(std::ceil((wanted_px - options_.disparity.min_disparity + 1) / 16.0)) * 16);
}

double FrameAnalyzer::ModelMaxDisparityPx(const Eigen::Isometry3d& tanker_from_receiver) const {
  // Depth along the left optical axis of the nearest model point; d = f b / z.
  const Eigen::Isometry3d left_from_receiver = tanker_from_left_.inverse() * tanker_from_receiver;
  double min_z = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& m : model_points_) min_z = std::min(min_z, (left_from_receiver * m).z());
  return min_z > 0.0 ? focal_times_baseline_px_m_ / min_z : std::numeric_limits<double>::infinity();
}

DisparityMap FrameAnalyzer::Match(const cv::Mat& rect_left, const cv::Mat& rect_right, const cv::Rect& region,
                                  const DisparityOptions& disparity_options, const BoomMasks* boom, FrameResult& r,
                                  FrameDump* dump) const {
  const auto start = std::chrono::steady_clock::now();
  DisparityMap disparity = ComputeDisparity(rect_left, rect_right, disparity_options);
  if (options_.remove_halo) RemoveHalo(disparity.disparity16, disparity.invalid_value16, options_.halo);
  if (options_.remove_clipped) {
    RemoveClippedMatches(disparity.disparity16, disparity.invalid_value16, rect_left, rect_right, options_.clipped);
  }
  if (boom != nullptr)
    BoomMasker::RemoveDisparities(disparity.disparity16, disparity.invalid_value16, region.tl(), *boom);
  r.times.disparity_ms += MillisecondsSince(start);
  if (dump != nullptr) {
    dump->disparity16 = disparity.disparity16;
    dump->region = region;
    dump->invalid_value16 = disparity.invalid_value16;
    dump->sensed_in_tanker.clear();
  }
  return disparity;
}

StereoTruthOptions FrameAnalyzer::TruthOptions(const FrameResult& r) const {
  StereoTruthOptions options;
  options.rect_left_from_receiver = tanker_from_rect_left_.inverse() * IsometryFromPose(r.truth);
  return options;
}

void FrameAnalyzer::CompareCloudWithTruth(const DepthTruth& truth, SensedCloud& cloud, FrameResult& r,
                                          std::vector<size_t>& blades) const {
  std::vector<Eigen::Vector3d> ideal;
  r.stereo_truth = CompareWithTruth(cloud.pixels, truth, calibration_, TruthOptions(r),
                                    options_.register_truth_cloud ? &ideal : nullptr, nullptr, &blades);
  if (!options_.register_truth_cloud) return;
  cloud.points_in_tanker.clear();
  RandomStream noise(0x9E3779B97F4A7C15ull * (r.frame + 1));
  for (Eigen::Vector3d p : ideal) {
    if (options_.truth_cloud_noise_px > 0.0) {
      const double d = focal_times_baseline_px_m_ / p.z();
      p *= d / (d + options_.truth_cloud_noise_px * noise.Normal());
    }
    cloud.points_in_tanker.push_back(tanker_from_rect_left_ * p);
  }
}

size_t FrameAnalyzer::PropellersKept(const SensedCloud& cloud, const std::vector<size_t>& blades,
                                     const RegistrationResult& icp) const {
  std::vector<Eigen::Vector3d> on_blades;
  for (size_t i : blades) on_blades.push_back(cloud.points_in_tanker[i]);
  if (!options_.mask_propellers) return on_blades.size();
  return OutsidePropellerDiscs(on_blades, icp.tanker_from_receiver, tanker_from_rect_left_.translation(),
                               options_.propeller_mask, options_.propeller_mask.axial_half_width_m)
      .size();
}

struct FrameAnalyzer::SensedRegion {
  cv::Mat rect_left, rect_right;
  std::unique_ptr<SubpixelRefiner> refiner;
  SensedCloud cloud;
};

FrameAnalyzer::SensedRegion FrameAnalyzer::Sense(const FrameInputs& in, const cv::Rect& region,
                                                 const DisparityOptions& disparity_options, FrameResult& r,
                                                 FrameDump* dump) const {
  SensedRegion sensed;
  auto start = std::chrono::steady_clock::now();
  rectifier_.Rectify(in.left, in.right, sensed.rect_left, sensed.rect_right, region);
  r.times.rectify_ms += MillisecondsSince(start);
  if (options_.refine_subpixel) {
    sensed.refiner =
        std::make_unique<SubpixelRefiner>(sensed.rect_left, sensed.rect_right, options_.subpixel, region.tl());
  }

  const DisparityMap disparity =
      Match(sensed.rect_left, sensed.rect_right, region, disparity_options, in.boom, r, dump);

  start = std::chrono::steady_clock::now();
  ReprojectionOptions reprojection = options_.reprojection;
  if (options_.remove_rounding_bias) reprojection.matcher_bias_px = MatcherRoundingBiasPx(disparity_options.algorithm);
  sensed.cloud = Reproject(disparity.disparity16, disparity.invalid_value16, calibration_, tanker_from_left_,
                           reprojection, sensed.refiner.get(), region.tl());
  r.sensed_points = sensed.cloud.points_in_tanker.size();
  r.times.reproject_ms += MillisecondsSince(start);
  if (sensed.cloud.points_in_tanker.size() < options_.min_sensed_points) {
    throw Error(in.left_path + ": only " + std::to_string(sensed.cloud.points_in_tanker.size()) +
                " sensed points (receiver out of view?)");
  }
  return sensed;
}

RegistrationResult FrameAnalyzer::Measure(const FrameInputs& in, const cv::Rect& roi, int num_disparities,
                                          const std::optional<Pose>& seed, FrameResult& r, FrameDump* dump) const {
  // The region computed: the receiver's predicted box and, to its left, the
  // columns its matches can come from (the disparity search and a block).
  DisparityOptions disparity_options = options_.disparity;
  if (num_disparities > 0) disparity_options.num_disparities = num_disparities;
  const cv::Rect image(0, 0, rectifier_.image_size().width, rectifier_.image_size().height);
  const auto compute_region = [&](const DisparityOptions& d) {
    if (roi.area() == 0) return image;
    const int reach = d.min_disparity + d.num_disparities + d.block_size;
    return cv::Rect(cv::Point(roi.x - reach, roi.y - d.block_size), cv::Point(roi.br().x, roi.br().y + d.block_size)) &
           image;
  };
  RegistrationResult icp;
  r.times.rectify_ms = r.times.disparity_ms = r.times.reproject_ms = r.times.icp_ms = 0.0;
  for (int attempt = 0;; ++attempt) {
    const cv::Rect region = compute_region(disparity_options);
    SensedRegion sensed = Sense(in, region, disparity_options, r, dump);
    SensedCloud& cloud = sensed.cloud;
    std::vector<size_t> blades;  // the sensed points on the propeller blades (depth truth)
    if (in.truth) CompareCloudWithTruth(*in.truth, cloud, r, blades);

    if (dump != nullptr) dump->sensed_in_tanker = cloud.points_in_tanker;

    const auto start = std::chrono::steady_clock::now();
    icp = Register(cloud.points_in_tanker, seed);
    MaskPropellersAndRegister(cloud.points_in_tanker, icp);
    const bool corrected = options_.correct_window_bias && sensed.refiner && receiver_mesh_ &&
                           !options_.register_truth_cloud &&
                           CorrectWindowBias(sensed.rect_left, sensed.rect_right, region, cloud, icp);
    if (options_.refine_direct && receiver_mesh_ && !options_.register_truth_cloud) {
      RefineDirectly(sensed.rect_left, sensed.rect_right, region, icp);
    }
    if (dump != nullptr) {
      dump->sensed_in_tanker = cloud.points_in_tanker;
      dump->pixels = cloud.pixels;
      dump->true_disparity_px.clear();
    }
    r.times.icp_ms += MillisecondsSince(start);
    if (in.truth && (corrected || dump != nullptr)) {
      r.stereo_truth = CompareWithTruth(cloud.pixels, *in.truth, calibration_, TruthOptions(r), nullptr,
                                        dump != nullptr ? &dump->true_disparity_px : nullptr);
    }
    // The ideal cloud (register_truth_cloud) is not the sensed pixels'.
    if (in.truth && !options_.register_truth_cloud) r.stereo_truth.propellers_kept = PropellersKept(cloud, blades, icp);
    // Near frames: part of the receiver beyond the search gives no (or
    // wrong) disparities; search again up to what the estimate needs.
    const double needed_px = ModelMaxDisparityPx(icp.tanker_from_receiver);
    const int searched_max = disparity_options.min_disparity + disparity_options.num_disparities - 1;
    if (!(needed_px > searched_max)) break;
    if (!options_.widen_disparity_search) break;  // the thesis: what the search covers
    if (attempt > 0 || !std::isfinite(needed_px) || needed_px > 250.0) {
      r.estimate = PoseFromIsometry(icp.tanker_from_receiver);
      r.error = PoseError(r.estimate, r.truth);
      r.has_estimate = true;
      throw Error(in.left_path + ": out of stereo range (the receiver needs " + FormatFixed(needed_px, 0) +
                  " px of disparity, the search covers " + std::to_string(searched_max) + ")");
    }
    disparity_options.num_disparities = DisparitiesFor(needed_px);
  }
  return icp;
}

cv::Rect FrameAnalyzer::PredictedRegion(const Eigen::Isometry3d& tanker_from_receiver, double margin_fraction,
                                        int margin_px) const {
  // Model points in the rectified left image: (f x / z + cx, f y / z + cy).
  const double f = calibration_.P1.at<double>(0, 0), cx = calibration_.P1.at<double>(0, 2);
  const double fy = calibration_.P1.at<double>(1, 1), cy = calibration_.P1.at<double>(1, 2);
  const Eigen::Isometry3d rect_left_from_receiver = tanker_from_rect_left_.inverse() * tanker_from_receiver;
  double u0 = std::numeric_limits<double>::infinity(), v0 = u0, u1 = -u0, v1 = -u0;
  for (const Eigen::Vector3d& m : model_points_) {
    const Eigen::Vector3d p = rect_left_from_receiver * m;
    if (!(p.z() > 0.0)) return cv::Rect();  // behind the camera: no region
    u0 = std::min(u0, f * p.x() / p.z() + cx);
    u1 = std::max(u1, f * p.x() / p.z() + cx);
    v0 = std::min(v0, fy * p.y() / p.z() + cy);
    v1 = std::max(v1, fy * p.y() / p.z() + cy);
  }
  const double mu = margin_fraction * (u1 - u0) + margin_px, mv = margin_fraction * (v1 - v0) + margin_px;
  const cv::Rect image(0, 0, rectifier_.image_size().width, rectifier_.image_size().height);
  const cv::Rect box(cv::Point(static_cast<int>(std::floor(u0 - mu)), static_cast<int>(std::floor(v0 - mv))),
                     cv::Point(static_cast<int>(std::ceil(u1 + mu)) + 1, static_cast<int>(std::ceil(v1 + mv)) + 1));
  return box & image;
}

std::string FrameAnalyzer::RegistrationFailure(const RegistrationResult& reg, size_t sensed_points) const {
  const double range_m = (reg.tanker_from_receiver.translation() - tanker_from_left_.translation()).norm();
  const double sigma_z = range_m * range_m * options_.disparity_noise_px / focal_times_baseline_px_m_;
  const double limit_m = options_.max_icp_rmse_m + 3.0 * sigma_z;
  if (!reg.tanker_from_receiver.matrix().allFinite() || !(reg.rmse_m <= limit_m)) {
    return "ICP did not converge (residual " + FormatFixed(reg.rmse_m, 3) + " m, limit " + FormatFixed(limit_m, 3) +
           " m at " + FormatFixed(range_m, 1) + " m)";
  }
  if (static_cast<double>(reg.num_inliers) < options_.min_inlier_fraction * static_cast<double>(sensed_points)) {
    return "ICP lost the receiver (" + std::to_string(reg.num_inliers) + " of " + std::to_string(sensed_points) +
           " sensed points paired)";
  }
  return "";
}

RegistrationResult FrameAnalyzer::MeasureFrame(const FrameInputs& in, const std::optional<Pose>& predicted,
                                               const std::optional<Pose>& seed, FrameResult& r, FrameDump* dump,
                                               std::string& why) const {
  RegistrationResult icp;
  try {
    bool measured = false;
    StageTimes lost_times;  // spent on a region the receiver was not (all) in
    if (options_.track_region && predicted) {
      const cv::Rect roi = PredictedRegion(IsometryFromPose(*predicted));
      if (roi.area() > 0) {
        FrameResult attempt = r;
        // The disparities the predicted receiver needs, when fewer than the options search.
        const int num_disparities = std::min(options_.disparity.num_disparities,
                                             DisparitiesFor(ModelMaxDisparityPx(IsometryFromPose(*predicted))));
        try {
          icp = Measure(in, roi, num_disparities, seed, attempt, dump);
          // Lost when the receiver reaches the region's border: measure the whole image.
          const cv::Rect estimated = PredictedRegion(icp.tanker_from_receiver, 0.0, 0);
          measured = estimated.area() > 0 && (estimated & roi) == estimated;
        } catch (const std::exception&) {  // aar::Error, or OpenCV's on a region too small to match
          measured = false;
        }
        if (measured) {
          r = attempt;
        } else {
          lost_times = attempt.times;
        }
      }
    }
    if (!measured) {
      icp = Measure(in, cv::Rect(), 0, seed, r, dump);
      AddAttemptTimes(r.times, lost_times);
    }
    why = RegistrationFailure(icp, r.sensed_points);
  } catch (const std::exception& e) {
    if (!seed) throw;
    why = e.what();
  }
  if (!why.empty() && seed) {
    // Tracking from the last estimate went wrong: the centroid, the whole image.
    const StageTimes spent = r.times;
    icp = Measure(in, cv::Rect(), 0, std::nullopt, r, dump);
    AddAttemptTimes(r.times, spent);
    why = RegistrationFailure(icp, r.sensed_points);
  }
  return icp;
}

FrameResult FrameAnalyzer::Analyze(const OpenedDataset& dataset, size_t index, const TrackHistory& history,
                                   FrameDump* dump, std::optional<DepthTruth>* depth_truth) const {
  const auto frame_start = std::chrono::steady_clock::now();
  FrameResult r;
  r.frame = index;
  if (depth_truth != nullptr) depth_truth->reset();
  try {
    auto start = std::chrono::steady_clock::now();
    const FrameSidecar sidecar = dataset.Sidecar("frame", index);
    r.time_s = sidecar.time_s;
    r.truth = sidecar.tanker_from_target;
    r.range_m = sidecar.range_m;
    r.region = RegionForRange(sidecar.range_m);
    FrameInputs in;
    const bool thermal = dataset.has_rig() && dataset.rig().lwir.has_value();
    in.left = ReadImage(dataset, sidecar.files.at("left"), thermal ? cv::IMREAD_UNCHANGED : cv::IMREAD_COLOR);
    in.right = ReadImage(dataset, sidecar.files.at("right"), thermal ? cv::IMREAD_UNCHANGED : cv::IMREAD_COLOR);
    in.left_path = dataset.PathOf(sidecar.files.at("left").path);
    if (thermal) WindowThermalPair(in.left, in.right, in.left_path);
    if (in.left.size() != rectifier_.image_size() || in.right.size() != rectifier_.image_size()) {
      throw Error(in.left_path + ": image size differs from the calibration's");
    }
    r.times.load_ms = MillisecondsSince(start);
    if (dump != nullptr) {
      dump->left_bgr = in.left;
      dump->tanker_from_receiver_truth = IsometryFromPose(r.truth);
    }
    if (options_.compare_with_truth && sidecar.files.count("left_depth") && sidecar.files.count("left_mask")) {
      in.truth = ReadDepthTruth(dataset.folder() / sidecar.files.at("left_depth").path,
                                dataset.folder() / sidecar.files.at("left_mask").path);
      if (depth_truth != nullptr) *depth_truth = in.truth;
    } else if (options_.register_truth_cloud) {
      throw Error(in.left_path + ": no depth truth for the ideal cloud (render with --depth)");
    }
    // The boom: what the tanker's telemetry says it covers (--mask-boom), and
    // how much of the receiver the truth says it hides (reported, not used).
    std::optional<BoomMasks> boom_masks;
    if (boom_masker_ && sidecar.boom) boom_masks = boom_masker_->Draw(*sidecar.boom);
    if (sidecar.boom && sidecar.files.count("left_mask") && sidecar.files.count("left_silhouette")) {
      // The id mask was read with the depth truth when the run compares with it.
      r.receiver_occluded_fraction = ReceiverOccludedFraction(
          in.truth ? in.truth->ids : ReadImage(dataset, sidecar.files.at("left_mask"), cv::IMREAD_GRAYSCALE),
          ReadImage(dataset, sidecar.files.at("left_silhouette"), cv::IMREAD_GRAYSCALE));
    }
    in.boom = boom_masks ? &*boom_masks : nullptr;
    std::string why;
    const RegistrationResult icp =
        MeasureFrame(in, PredictedPose(history, r.time_s), SeedFromHistory(history, options_), r, dump, why);
    r.icp_iterations = icp.iterations;
    r.icp_converged = icp.converged;
    r.icp_rmse_m = icp.rmse_m;
    r.icp_inliers = icp.num_inliers;
    if (icp.tanker_from_receiver.matrix().allFinite()) {
      r.estimate = PoseFromIsometry(icp.tanker_from_receiver);
      r.error = PoseError(r.estimate, r.truth);
      r.has_estimate = true;
    }
    if (!why.empty()) throw Error(in.left_path + ": " + why);
    r.status = "ok";
  } catch (const std::exception& e) {  // aar::Error, json or OpenCV errors: the frame is not measured
    r.status = e.what();
  }
  if (dump != nullptr && r.has_estimate) dump->tanker_from_receiver = IsometryFromPose(r.estimate);
  r.times.total_ms = MillisecondsSince(frame_start);
  return r;
}

}  // namespace aar
