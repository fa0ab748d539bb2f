#include "aar/analyzer/vsd.h"

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "aar/error.h"

namespace aar {

VsdErrors VsdFromDepth(const DepthBuffer& estimate, const DepthBuffer& truth, const cv::Mat& test_depth_m,
                       const Intrinsics& camera, double diameter_m, double delta_m) {
  const int w = camera.width_px, h = camera.height_px;
  const auto size_text = [](int width, int height) { return std::to_string(width) + "x" + std::to_string(height); };
  if (test_depth_m.type() != CV_32FC1 || test_depth_m.cols != w || test_depth_m.rows != h) {
    throw Error("VSD: the test depth is not a " + size_text(w, h) + " float image");
  }
  if (estimate.width != w || estimate.height != h || truth.width != w || truth.height != h) {
    throw Error("VSD: the renderings are not " + size_text(w, h));
  }
  if (!(diameter_m > 0.0)) throw Error("VSD: the object's diameter must be positive");

  // Distance from the camera's centre over depth along its axis, per pixel.
  const auto ray_length = [&camera](int x, int y) {
    const double a = (x - camera.cx_px) / camera.fx_px, b = (y - camera.cy_px) / camera.fy_px;
    return std::sqrt(1.0 + a * a + b * b);
  };
  size_t union_count = 0, exclusive_count = 0;
  std::vector<double> inter_distances;  // |S' - S| over V and V', in diameters
  for (int y = 0; y < h; ++y) {
    const float* test_row = test_depth_m.ptr<float>(y);
    for (int x = 0; x < w; ++x) {
      const float s = truth.At(x, y), s_est = estimate.At(x, y);
      const bool truth_rendered = std::isfinite(s), estimate_rendered = std::isfinite(s_est);
      if (!truth_rendered && !estimate_rendered) continue;
      const double ray = ray_length(x, y);
      const double test = static_cast<double>(test_row[x]) * ray;
      const bool test_missing = test_row[x] == 0.0f;
      const double truth_dist = static_cast<double>(s) * ray, estimate_dist = static_cast<double>(s_est) * ray;
      const bool visible = truth_rendered && (test_missing || truth_dist - test <= delta_m);
      const bool visible_est = estimate_rendered && (test_missing || estimate_dist - test <= delta_m || visible);
      if (!visible && !visible_est) continue;
      ++union_count;
      if (visible && visible_est) {
        inter_distances.push_back(std::abs(estimate_dist - truth_dist) / diameter_m);
      } else {
        ++exclusive_count;
      }
    }
  }
  VsdErrors errors;
  for (size_t t = 0; t < kVsdTauFractions.size(); ++t) {
    if (union_count == 0) {
      errors[t] = 1.0;
      continue;
    }
    size_t misaligned = 0;
    for (double d : inter_distances) misaligned += d >= kVsdTauFractions[t] ? 1 : 0;
    errors[t] = static_cast<double>(misaligned + exclusive_count) / static_cast<double>(union_count);
  }
  return errors;
}

VsdErrors ComputeVsd(const TriangleMesh& mesh, const Intrinsics& camera,
                     const Eigen::Isometry3d& cam_from_model_estimate, const Eigen::Isometry3d& cam_from_model_truth,
                     const cv::Mat& test_depth_m, double diameter_m, double near_m) {
  const DepthBuffer estimate = RasterizeDepth(mesh, camera, cam_from_model_estimate, near_m);
  const DepthBuffer truth = RasterizeDepth(mesh, camera, cam_from_model_truth, near_m);
  return VsdFromDepth(estimate, truth, test_depth_m, camera, diameter_m, kVsdDeltaM);
}

}  // namespace aar
