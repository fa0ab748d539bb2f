#include "aar/renderer/sun_camera.h"

#include <algorithm>
#include <cmath>

#include "aar/error.h"

namespace aar {

Camera SunCamera(const Eigen::Vector3d& sun_in_tanker, const Eigen::Vector3d& centre_in_tanker, double radius_m,
                 int width_px, int height_px) {
  if (!(std::abs(sun_in_tanker.norm() - 1.0) < 1e-6))
    throw Error("sun camera: the sun's direction must be a unit vector");
  if (!(radius_m > 0.0 && radius_m < 0.1 * kSunCameraDistanceM)) {
    throw Error("sun camera: the framed sphere's radius must be in (0, " + std::to_string(0.1 * kSunCameraDistanceM) +
                ") m");
  }
  if (width_px < 8 || height_px < 8) throw Error("sun camera: the map must be at least 8 x 8 texels");
  const Eigen::Vector3d z = -sun_in_tanker;  // looking from the sun
  Eigen::Vector3d x = sun_in_tanker.cross(Eigen::Vector3d::UnitZ());
  x = x.norm() > 1e-6 ? x.normalized() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d y = z.cross(x);
  Camera camera;
  camera.tanker_from_camera.linear().col(0) = x;
  camera.tanker_from_camera.linear().col(1) = y;
  camera.tanker_from_camera.linear().col(2) = z;
  camera.tanker_from_camera.translation() = centre_in_tanker + kSunCameraDistanceM * sun_in_tanker;
  Intrinsics& k = camera.intrinsics;
  k.width_px = width_px;
  k.height_px = height_px;
  const double half_side_px = 0.5 * std::min(width_px, height_px) - 2.0;
  const double tan_half_angle = radius_m / std::sqrt(kSunCameraDistanceM * kSunCameraDistanceM - radius_m * radius_m);
  k.fx_px = k.fy_px = half_side_px / tan_half_angle;
  k.cx_px = 0.5 * (width_px - 1);
  k.cy_px = 0.5 * (height_px - 1);
  return camera;
}

}  // namespace aar
