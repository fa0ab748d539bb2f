#include "aar/analyzer/direct_stereo.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "aar/analyzer/window_bias.h"
#include "aar/error.h"

namespace aar {

namespace {

constexpr double kNearM = 0.1;                   // the model's rasterization near plane [m]
constexpr size_t kMinPixels = 64;                // fewer usable pixels: no refinement
constexpr int kMaxFixedPointSteps = 20;          // the cyclopean disparity's fixed point: steps at most
constexpr double kFixedPointTolerancePx = 1e-4;  // and the step below which it has converged [px]
constexpr double kMadToSigma = 1.4826;           // median absolute deviation to a Gaussian's standard deviation

// The rectified camera: focal lengths, principal point (image pixels), and Q's disparity terms.
struct RectifiedCamera {
  double f = 0.0, fy = 0.0, cx = 0.0, cy = 0.0, q23 = 0.0, q32 = 0.0, q33 = 0.0;
  explicit RectifiedCamera(const StereoCalibration& calibration) {
    cv::Mat p1, q;
    calibration.P1.convertTo(p1, CV_64F);
    calibration.Q.convertTo(q, CV_64F);
    f = p1.at<double>(0, 0);
    fy = p1.at<double>(1, 1);
    cx = p1.at<double>(0, 2);
    cy = p1.at<double>(1, 2);
    q23 = q.at<double>(2, 3);
    q32 = q.at<double>(3, 2);
    q33 = q.at<double>(3, 3);
  }
  double Depth(double d) const { return q23 / (q32 * d + q33); }
  Eigen::Vector3d Ray(double u, double v) const { return {(u - cx) / f, (v - cy) / fy, 1.0}; }
};

// Horizontal central difference of an 8-bit image as float (0 at the borders).
cv::Mat HorizontalGradient(const cv::Mat& image) {
  cv::Mat g(image.size(), CV_32F, cv::Scalar(0));
  for (int y = 0; y < image.rows; ++y) {
    const uint8_t* in = image.ptr<uint8_t>(y);
    float* out = g.ptr<float>(y);
    for (int x = 1; x + 1 < image.cols; ++x) out[x] = 0.5F * (static_cast<float>(in[x + 1]) - in[x - 1]);
  }
  return g;
}

template <typename T>
double Bilinear(const cv::Mat& image, double x, int y) {
  const int x0 = static_cast<int>(std::floor(x));
  const double a = x - x0;
  const T* row = image.ptr<T>(y);
  return (1.0 - a) * static_cast<double>(row[x0]) + a * static_cast<double>(row[x0 + 1]);
}

// The pixels of the model's disparity map the fit may use (CV_8U, 255):
// covered with their 4-neighbours and no depth step to them, eroded by the
// margin, and not hidden from the right camera by the model itself.
cv::Mat UsablePixels(const cv::Mat& disparity, const DirectStereoOptions& options) {
  cv::Mat usable(disparity.size(), CV_8U, cv::Scalar(0));
  for (int y = 1; y + 1 < disparity.rows; ++y) {
    for (int x = 1; x + 1 < disparity.cols; ++x) {
      const float d = disparity.at<float>(y, x);
      if (!std::isfinite(d)) continue;
      bool smooth = true;
      for (const cv::Point step : {cv::Point(1, 0), cv::Point(-1, 0), cv::Point(0, 1), cv::Point(0, -1)}) {
        const float n = disparity.at<float>(y + step.y, x + step.x);
        smooth = smooth && std::isfinite(n) && std::abs(n - d) <= options.max_step_px;
      }
      if (smooth) usable.at<uint8_t>(y, x) = 255;
    }
  }
  if (options.edge_margin_px > 0) {
    const int size = 2 * options.edge_margin_px + 1;
    cv::erode(usable, usable, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(size, size)));
  }
  // Right-camera self-occlusion: a pixel is hidden in the right image, or
  // within the margin of an occluding edge there, when a nearer surface
  // point to its right in the left image (a larger disparity) lands at or
  // left of its own right-image position plus the margin.
  double max_disparity = -std::numeric_limits<double>::infinity();
  for (int y = 0; y < disparity.rows; ++y) {
    for (int x = 0; x < disparity.cols; ++x) {
      const float d = disparity.at<float>(y, x);
      if (std::isfinite(d)) max_disparity = std::max(max_disparity, static_cast<double>(d));
    }
  }
  const double margin = std::max(0.5, static_cast<double>(options.edge_margin_px));
  for (int y = 0; y < disparity.rows; ++y) {
    const float* row = disparity.ptr<float>(y);
    for (int x = 0; x < disparity.cols; ++x) {
      if (usable.at<uint8_t>(y, x) == 0) continue;
      const double d = row[x];
      const double reach = x + (max_disparity - d) + margin;
      for (int x2 = x + 1; x2 < disparity.cols && x2 <= reach; ++x2) {
        const double d2 = row[x2];
        if (std::isfinite(d2) && d2 > d + options.max_step_px && x2 - d2 <= x - d + margin) {
          usable.at<uint8_t>(y, x) = 0;
          break;
        }
      }
    }
  }
  return usable;
}

// One Gauss-Newton system over the usable pixels at one pose.
struct NormalEquations {
  Eigen::Matrix<double, 6, 6> h = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
  size_t pixels = 0;
  double sigma = 0.0;
};

struct PixelTerm {
  double residual;
  Eigen::Matrix<double, 6, 1> jacobian;
};

// Residuals and Jacobians at the cyclopean positions c = x of every row:
// the surface point seen at c + d / 2 in the left image and at c - d / 2 in
// the right, where d is the model's disparity there (d = D(c + d / 2), a
// fixed point). Both images are then interpolated at complementary
// fractions, so that linear interpolation smooths them alike and pulls no
// disparity towards whole pixels.
std::vector<PixelTerm> PixelTerms(const cv::Mat& disparity, const cv::Mat& usable, const cv::Mat& left,
                                  const cv::Mat& right, const cv::Mat& gradient_left, const cv::Mat& gradient_right,
                                  const cv::Point origin, const RectifiedCamera& camera,
                                  const DirectStereoOptions& options) {
  std::vector<PixelTerm> terms;
  const auto point = [&](int x, int y) {
    const double z = camera.Depth(disparity.at<float>(y, x));
    return Eigen::Vector3d(z * camera.Ray(x + origin.x, y + origin.y));
  };
  const auto usable_at = [&](double x, int y) {
    const int x0 = static_cast<int>(std::floor(x));
    return x0 >= 1 && x0 + 2 < usable.cols && usable.at<uint8_t>(y, x0) != 0 && usable.at<uint8_t>(y, x0 + 1) != 0;
  };
  for (int y = 1; y + 1 < disparity.rows; ++y) {
    for (int x = 1; x + 1 < disparity.cols; ++x) {
      if (usable.at<uint8_t>(y, x) == 0) continue;
      double d = disparity.at<float>(y, x);
      // Fixed-point steps contract by |s| / 2 (s the disparity's slope along
      // the row): iterate to convergence, a slanted surface's first steps
      // are tenths of a pixel off.
      bool inside = true, settled = false;
      for (int step = 0; step < kMaxFixedPointSteps && inside && !settled; ++step) {
        inside = usable_at(x + 0.5 * d, y);
        if (!inside) break;
        const double next = Bilinear<float>(disparity, x + 0.5 * d, y);
        settled = std::abs(next - d) < kFixedPointTolerancePx;
        d = next;
      }
      inside = inside && settled;
      const double at_left = x + 0.5 * d, at_right = x - 0.5 * d;
      if (!inside || !usable_at(at_left, y) || !(at_right >= 1.0 && at_right < right.cols - 2.0)) continue;
      const int near = static_cast<int>(std::lround(at_left));
      const Eigen::Vector3d w = camera.Ray(at_left + origin.x, y + origin.y);
      const double z = camera.Depth(d);
      const Eigen::Vector3d p = z * w;
      Eigen::Vector3d n = (point(near + 1, y) - point(near - 1, y)).cross(point(near, y + 1) - point(near, y - 1));
      if (!(n.norm() > 0.0)) continue;
      n.normalize();
      const double n_dot_w = n.dot(w);
      if (!(std::abs(n_dot_w) >= options.min_cos_incidence * w.norm())) continue;
      // dd/dxi at fixed c: the model's dD/dxi at c + d / 2 over (1 - s / 2),
      // s its slope dD/du there; dD/dxi = dD/dz dz/dxi, xi = (omega, t) in
      // the rectified left camera.
      const double slope = 0.5 * (disparity.at<float>(y, near + 1) - disparity.at<float>(y, near - 1));
      const double dd_dz = -camera.q23 / (camera.q32 * z * z) / (1.0 - 0.5 * slope);
      Eigen::Matrix<double, 6, 1> dz;
      dz << p.cross(n) / n_dot_w, n / n_dot_w;
      const double g =
          0.5 * (Bilinear<float>(gradient_left, at_left, y) + Bilinear<float>(gradient_right, at_right, y));
      PixelTerm term;
      term.residual = Bilinear<uint8_t>(right, at_right, y) - Bilinear<uint8_t>(left, at_left, y);
      term.jacobian = -g * dd_dz * dz;
      terms.push_back(term);
    }
  }
  return terms;
}

NormalEquations Accumulate(const std::vector<PixelTerm>& terms, double huber_k) {
  NormalEquations eq;
  eq.pixels = terms.size();
  if (terms.empty()) return eq;
  std::vector<double> magnitudes(terms.size());
  for (size_t i = 0; i < terms.size(); ++i) magnitudes[i] = std::abs(terms[i].residual);
  std::nth_element(magnitudes.begin(), magnitudes.begin() + magnitudes.size() / 2, magnitudes.end());
  eq.sigma = kMadToSigma * magnitudes[magnitudes.size() / 2];
  const double threshold = huber_k * std::max(eq.sigma, 1e-3);
  for (const PixelTerm& t : terms) {
    const double weight = std::abs(t.residual) <= threshold ? 1.0 : threshold / std::abs(t.residual);
    eq.h += weight * t.jacobian * t.jacobian.transpose();
    eq.b += weight * t.residual * t.jacobian;
  }
  return eq;
}

// The Gauss-Newton step: all six components, or the translation alone.
Eigen::Matrix<double, 6, 1> Step(const NormalEquations& eq, DirectStereoFit fit) {
  if (fit == DirectStereoFit::kPose) return eq.h.ldlt().solve(-eq.b);
  Eigen::Matrix<double, 6, 1> step = Eigen::Matrix<double, 6, 1>::Zero();
  step.tail<3>() = eq.h.bottomRightCorner<3, 3>().ldlt().solve(-eq.b.tail<3>());
  return step;
}

Eigen::Isometry3d Exp(const Eigen::Matrix<double, 6, 1>& step) {
  Eigen::Isometry3d change = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d omega = step.head<3>();
  if (omega.norm() > 0.0) change.linear() = Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix();
  change.translation() = step.tail<3>();
  return change;
}

// How far the fit moved the model in the rectified images: the largest
// change of a bounding-box corner's column, row or disparity [px] (infinite
// when a corner is not in front of the cameras at both poses).
double ImageMotionPx(const TriangleMesh& mesh, const RectifiedCamera& camera, const Eigen::Isometry3d& from,
                     const Eigen::Isometry3d& to) {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& v : mesh.vertices) box.extend(v);
  const auto project = [&](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(camera.f * p.x() / p.z(), camera.fy * p.y() / p.z(), camera.q23 / (camera.q32 * p.z()));
  };
  double motion = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d c = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(corner));
    const Eigen::Vector3d a = from * c, b = to * c;
    if (!(a.z() > kNearM && b.z() > kNearM)) return std::numeric_limits<double>::infinity();
    motion = std::max(motion, (project(a) - project(b)).cwiseAbs().maxCoeff());
  }
  return std::isfinite(motion) ? motion : std::numeric_limits<double>::infinity();
}

}  // namespace

std::string ToString(DirectStereoFit fit) { return fit == DirectStereoFit::kPose ? "pose" : "translation"; }

DirectStereoFit ParseDirectStereoFit(const std::string& text) {
  if (text == "translation") return DirectStereoFit::kTranslation;
  if (text == "pose") return DirectStereoFit::kPose;
  throw Error("direct stereo fit must be translation or pose, not '" + text + "'");
}

void DirectStereoOptions::Check() const {
  if (iterations < 1 || iterations > 100) throw Error("direct stereo: iterations must be in [1, 100]");
  if (edge_margin_px < 0 || edge_margin_px > 32) throw Error("direct stereo: edge_margin_px must be in [0, 32]");
  if (!(max_step_px > 0.0)) throw Error("direct stereo: max_step_px must be positive");
  if (!(min_cos_incidence >= 0.0 && min_cos_incidence < 1.0)) {
    throw Error("direct stereo: min_cos_incidence must be in [0, 1)");
  }
  if (!(huber_k > 0.0)) throw Error("direct stereo: huber_k must be positive");
  if (!(converged_m > 0.0)) throw Error("direct stereo: converged_m must be positive");
  if (!(max_motion_px > 0.0)) throw Error("direct stereo: max_motion_px must be positive");
}

DirectStereoResult RefineDirectStereo(const TriangleMesh& mesh, const StereoCalibration& calibration,
                                      const cv::Mat& rect_left, const cv::Mat& rect_right, const cv::Rect& region,
                                      const Eigen::Isometry3d& rect_left_from_receiver,
                                      const DirectStereoOptions& options) {
  options.Check();
  if (rect_left.type() != CV_8UC1 || rect_right.type() != CV_8UC1 || rect_left.size() != region.size() ||
      rect_right.size() != region.size()) {
    throw Error("direct stereo: the rectified images must be 8-bit grey and region-sized");
  }
  const RectifiedCamera camera(calibration);
  const cv::Mat gradient_left = HorizontalGradient(rect_left), gradient_right = HorizontalGradient(rect_right);
  // The model's extent, for the convergence test's lever arm.
  double extent_m = 0.0;
  for (const Eigen::Vector3d& v : mesh.vertices) extent_m = std::max(extent_m, v.norm());
  DirectStereoResult result;
  result.rect_left_from_receiver = rect_left_from_receiver;
  Eigen::Isometry3d pose = rect_left_from_receiver;
  for (int iteration = 0; iteration < options.iterations; ++iteration) {
    const cv::Mat disparity = ModelDisparity(mesh, calibration, pose, region, kNearM);
    const cv::Mat usable = UsablePixels(disparity, options);
    const NormalEquations eq = Accumulate(PixelTerms(disparity, usable, rect_left, rect_right, gradient_left,
                                                     gradient_right, region.tl(), camera, options),
                                          options.huber_k);
    if (eq.pixels < kMinPixels) break;
    const Eigen::Matrix<double, 6, 1> step = Step(eq, options.fit);
    if (!step.allFinite()) break;
    pose = Exp(step) * pose;
    result.pixels = eq.pixels;
    result.residual_sigma = eq.sigma;
    result.iterations = iteration + 1;
    if (step.head<3>().norm() * extent_m + step.tail<3>().norm() < options.converged_m) {
      result.converged = true;
      break;
    }
  }
  // A local refinement of a registration that is within a fraction of a
  // pixel: a fit that moved the model by more has left its basin.
  if (result.pixels > 0 && ImageMotionPx(mesh, camera, rect_left_from_receiver, pose) <= options.max_motion_px) {
    result.rect_left_from_receiver = pose;
  } else {
    result = DirectStereoResult{};
    result.rect_left_from_receiver = rect_left_from_receiver;
  }
  return result;
}

}  // namespace aar
