#include "aar/renderer/sun_glare.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "aar/error.h"

namespace aar {

double GlareSpread(double theta_rad, double fraction, double core_rad) {
  const double r2 = core_rad * core_rad + theta_rad * theta_rad;
  return fraction * core_rad / (2.0 * std::numbers::pi * r2 * std::sqrt(r2));
}

SunGlare::SunGlare(const Camera& camera, const Eigen::Vector3d& sun_in_tanker, const Eigen::Vector3d& sun_light,
                   double fraction, double core_deg)
    : width_(camera.intrinsics.width_px), height_(camera.intrinsics.height_px) {
  if (!(fraction > 0.0) || !(core_deg > 0.0)) throw Error("SunGlare: the fraction and the core angle must be positive");
  veil_.assign(static_cast<size_t>(width_) * height_ * 3, 0.0f);
  const Eigen::Vector3d sun = camera.tanker_from_camera.linear().transpose() * sun_in_tanker.normalized();
  const double aperture = sun.z();  // the cosine of the sun's angle to the optical axis
  if (aperture <= 0.0) return;
  const Eigen::Vector3d irradiance = std::numbers::pi * aperture * sun_light;
  const double core = core_deg * std::numbers::pi / 180.0;
  const Intrinsics& k = camera.intrinsics;
  for (int v = 0; v < height_; ++v) {
    for (int u = 0; u < width_; ++u) {
      const Eigen::Vector3d ray = Eigen::Vector3d((u - k.cx_px) / k.fx_px, (v - k.cy_px) / k.fy_px, 1.0).normalized();
      const double theta = 2.0 * std::asin(std::min(0.5 * (ray - sun).norm(), 1.0));
      const double g = GlareSpread(theta, fraction, core);
      float* out = &veil_[(static_cast<size_t>(v) * width_ + u) * 3];
      for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(g * irradiance[c]);
    }
  }
}

LinearImage SunGlare::Apply(const LinearImage& radiance, const SensorExposure&) const {
  if (radiance.width != width_ || radiance.height != height_) {
    throw Error("SunGlare: a " + std::to_string(radiance.width) + " x " + std::to_string(radiance.height) +
                " image for a " + std::to_string(width_) + " x " + std::to_string(height_) + " camera");
  }
  LinearImage out = radiance;
  for (size_t i = 0; i < out.rgb.size(); ++i) out.rgb[i] += veil_[i];
  return out;
}

}  // namespace aar
