#include "aar/renderer/projection.h"

namespace aar {

Eigen::Matrix4d ClipFromCamera(const Intrinsics& k, double near_m, double jitter_x_px, double jitter_y_px) {
  const double w = k.width_px;
  const double h = k.height_px;
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  // x_ndc = 2 (fx x/z + cx + 0.5 - jitter_x) / W - 1, likewise for y.
  m(0, 0) = 2.0 * k.fx_px / w;
  m(0, 2) = 2.0 * (k.cx_px + 0.5 - jitter_x_px) / w - 1.0;
  m(1, 1) = 2.0 * k.fy_px / h;
  m(1, 2) = 2.0 * (k.cy_px + 0.5 - jitter_y_px) / h - 1.0;
  m(2, 3) = near_m;  // z_clip = near, so z_ndc = near / z (reversed, infinite far plane)
  m(3, 2) = 1.0;     // w_clip = z_cam
  return m;
}

}  // namespace aar

namespace aar {

double InViewFraction(const std::vector<Eigen::Vector3d>& points_in_object, const Camera& camera,
                      const Eigen::Isometry3d& tanker_from_object) {
  if (points_in_object.empty()) return 0.0;
  const Eigen::Isometry3d cam_from_object = camera.tanker_from_camera.inverse() * tanker_from_object;
  size_t inside = 0;
  for (const Eigen::Vector3d& p : points_in_object) {
    const auto pixel = camera.intrinsics.Project(cam_from_object * p);
    if (pixel && camera.intrinsics.Contains(*pixel)) ++inside;
  }
  return static_cast<double>(inside) / static_cast<double>(points_in_object.size());
}

}  // namespace aar
