#include "aar/analyzer/stereo_truth.h"

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <limits>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgcodecs.hpp>

#include "aar/error.h"
#include "aar/lens.h"
#include "aar/propeller.h"

namespace aar {
namespace {

Eigen::MatrixXd ToEigen(const cv::Mat& m) {
  cv::Mat m64;
  m.convertTo(m64, CV_64F);
  Eigen::MatrixXd e;
  cv::cv2eigen(m64, e);
  return e;
}

}  // namespace

DepthTruth ReadDepthTruth(const std::filesystem::path& depth_exr, const std::filesystem::path& mask_png) {
  DepthTruth truth;
  auto in = OIIO::ImageInput::open(depth_exr.string());
  if (!in) throw Error(depth_exr.string() + ": cannot open depth image (" + OIIO::geterror() + ")");
  const OIIO::ImageSpec& spec = in->spec();
  // Depth is channel Y (readable by cv::imread); older renderers named it Z.
  int channel = -1;
  for (int c = 0; c < spec.nchannels && channel < 0; ++c) {
    const std::string& name = spec.channelnames[static_cast<size_t>(c)];
    if (name == "Y" || name == "Z") channel = c;
  }
  if (channel < 0) throw Error(depth_exr.string() + ": no depth channel (Y)");
  truth.depth_m.create(spec.height, spec.width, CV_32F);
  if (!in->read_image(0, 0, channel, channel + 1, OIIO::TypeDesc::FLOAT, truth.depth_m.data)) {
    throw Error(depth_exr.string() + ": cannot read depth (" + in->geterror() + ")");
  }
  truth.ids = cv::imread(mask_png.string(), cv::IMREAD_GRAYSCALE);
  if (truth.ids.empty()) throw Error(mask_png.string() + ": cannot read the object-id mask");
  if (truth.ids.size() != truth.depth_m.size())
    throw Error(mask_png.string() + ": size differs from the depth image's");
  return truth;
}

double StereoTruthStats::RmsErrorPx() const {
  return on_receiver ? std::sqrt(error_squared_sum_px2 / static_cast<double>(on_receiver)) : 0.0;
}

void StereoTruthStats::Add(const StereoTruthStats& o) {
  points += o.points;
  off_receiver += o.off_receiver;
  on_propellers += o.on_propellers;
  propellers_kept += o.propellers_kept;
  off_surface += o.off_surface;
  on_receiver += o.on_receiver;
  error_sum_px += o.error_sum_px;
  error_squared_sum_px2 += o.error_squared_sum_px2;
  for (size_t b = 0; b < kFractionBins; ++b) {
    bin_count[b] += o.bin_count[b];
    bin_error_sum_px[b] += o.bin_error_sum_px[b];
  }
}

bool OnPropellerBlade(const Eigen::Vector3d& point_in_receiver) {
  constexpr double kSlabHalfWidthM = 0.12, kInnerRadiusM = 0.35, kOuterRadiusM = 0.5 * kPropellerDiameterM + 0.05;
  for (const Eigen::Vector3d& hub : kPropellerHubsInReceiver) {
    const Eigen::Vector3d d = point_in_receiver - hub;  // the axis is the receiver's x
    const double radius = std::hypot(d.y(), d.z());
    if (std::abs(d.x()) <= kSlabHalfWidthM && radius >= kInnerRadiusM && radius <= kOuterRadiusM) return true;
  }
  return false;
}

StereoTruthStats CompareWithTruth(const std::vector<Eigen::Vector3d>& pixels, const DepthTruth& truth,
                                  const StereoCalibration& calibration, const StereoTruthOptions& options,
                                  std::vector<Eigen::Vector3d>* true_points_in_rect_left,
                                  std::vector<double>* true_disparity_px, std::vector<size_t>* on_propellers) {
  const Eigen::MatrixXd p1 = ToEigen(calibration.P1), r1 = ToEigen(calibration.R1), m1 = ToEigen(calibration.M1);
  const Eigen::MatrixXd q = ToEigen(calibration.Q);
  const double f = p1(0, 0), cx = p1(0, 2), cy = p1(1, 2), fy = p1(1, 1);
  const Eigen::Matrix3d left_from_rect = r1.transpose();
  const Eigen::Matrix3d k = m1;
  const Eigen::MatrixXd d1 = ToEigen(calibration.D1);
  const BrownConrady lens{d1(0, 0), d1(0, 1), d1(0, 2), d1(0, 3), d1(0, 4)};
  const int width = truth.depth_m.cols, height = truth.depth_m.rows;
  const auto id = [&](int x, int y) { return truth.ids.at<unsigned char>(y, x); };
  const auto depth = [&](int x, int y) { return static_cast<double>(truth.depth_m.at<float>(y, x)); };

  std::optional<Eigen::Isometry3d> receiver_from_rect;
  if (options.rect_left_from_receiver) receiver_from_rect = options.rect_left_from_receiver->inverse();
  StereoTruthStats stats;
  if (true_disparity_px != nullptr) true_disparity_px->assign(pixels.size(), std::numeric_limits<double>::quiet_NaN());
  for (size_t i = 0; i < pixels.size(); ++i) {
    const Eigen::Vector3d& pixel = pixels[i];
    ++stats.points;
    const Eigen::Vector3d ray_left = left_from_rect * Eigen::Vector3d((pixel.x() - cx) / f, (pixel.y() - cy) / fy, 1.0);
    // The truth images are the left camera's own, through its lens (D1).
    const Eigen::Vector2d distorted = Distort(lens, Eigen::Vector2d(ray_left.x(), ray_left.y()) / ray_left.z());
    const Eigen::Vector3d image = k * Eigen::Vector3d(distorted.x(), distorted.y(), 1.0);
    const double x = image.x(), y = image.y();
    const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
    const int xn = static_cast<int>(std::lround(x)), yn = static_cast<int>(std::lround(y));
    double z_left = 0.0;
    if (x0 >= 0 && y0 >= 0 && x0 + 1 < width && y0 + 1 < height && id(x0, y0) == kReceiverId &&
        id(x0 + 1, y0) == kReceiverId && id(x0, y0 + 1) == kReceiverId && id(x0 + 1, y0 + 1) == kReceiverId) {
      const double ax = x - x0, ay = y - y0;
      z_left = (1 - ay) * ((1 - ax) * depth(x0, y0) + ax * depth(x0 + 1, y0)) +
               ay * ((1 - ax) * depth(x0, y0 + 1) + ax * depth(x0 + 1, y0 + 1));
    } else if (xn >= 0 && yn >= 0 && xn < width && yn < height && id(xn, yn) == kReceiverId) {
      z_left = depth(xn, yn);
    }
    if (!(z_left > 0.0)) {
      ++stats.off_receiver;
      ++stats.off_surface;
      continue;
    }
    const Eigen::Vector3d point_in_rect = r1 * (ray_left * (z_left / ray_left.z()));
    if (true_points_in_rect_left != nullptr) true_points_in_rect_left->push_back(point_in_rect);
    const double d_true = (q(2, 3) / point_in_rect.z() - q(3, 3)) / q(3, 2);
    if (true_disparity_px != nullptr) (*true_disparity_px)[i] = d_true;
    const double error = pixel.z() - d_true;
    ++stats.on_receiver;
    if (receiver_from_rect && OnPropellerBlade(*receiver_from_rect * point_in_rect)) {
      ++stats.on_propellers;
      if (on_propellers != nullptr) on_propellers->push_back(i);
    }
    stats.error_sum_px += error;
    stats.error_squared_sum_px2 += error * error;
    const double fraction = d_true - std::floor(d_true);
    const size_t bin = std::min(kFractionBins - 1, static_cast<size_t>(fraction * kFractionBins));
    ++stats.bin_count[bin];
    stats.bin_error_sum_px[bin] += error;
    if (std::abs(error) > options.off_surface_px) ++stats.off_surface;
  }
  return stats;
}

}  // namespace aar
