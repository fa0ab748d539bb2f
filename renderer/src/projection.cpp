#include "aar/renderer/projection.h"

#include <algorithm>
#include <cmath>

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

namespace aar {

PixelRect ProjectedRect(const Eigen::Matrix4d& clip_from_object, const Eigen::AlignedBox3d& box, int width, int height,
                        int margin_px) {
  const PixelRect full{0, 0, width, height};
  if (box.isEmpty()) return PixelRect{};
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector4d clip =
        clip_from_object * box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i)).homogeneous();
    if (clip.w() <= 1e-6) return full;  // the box reaches behind the camera
    const double x = (clip.x() / clip.w() + 1.0) * width / 2.0;
    const double y = (clip.y() / clip.w() + 1.0) * height / 2.0;
    x0 = std::min(x0, x);
    y0 = std::min(y0, y);
    x1 = std::max(x1, x);
    y1 = std::max(y1, y);
  }
  PixelRect r;
  r.x0 = static_cast<int>(std::clamp(std::floor(x0) - margin_px, 0.0, static_cast<double>(width)));
  r.y0 = static_cast<int>(std::clamp(std::floor(y0) - margin_px, 0.0, static_cast<double>(height)));
  r.x1 = static_cast<int>(std::clamp(std::ceil(x1) + margin_px, 0.0, static_cast<double>(width)));
  r.y1 = static_cast<int>(std::clamp(std::ceil(y1) + margin_px, 0.0, static_cast<double>(height)));
  return r;
}

}  // namespace aar
