#include "aar/renderer/lens_flare.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "aar/error.h"

namespace aar {
namespace {

// The solid angle of pixel (u, v) of a pinhole camera [sr]: cos^3 of its
// ray's angle to the axis over fx fy.
double PixelSolidAngle(const Intrinsics& k, double u, double v) {
  const double x = (u - k.cx_px) / k.fx_px, y = (v - k.cy_px) / k.fy_px;
  const double cos_theta = 1.0 / std::sqrt(1.0 + x * x + y * y);
  return cos_theta * cos_theta * cos_theta / (k.fx_px * k.fy_px);
}

// A disc's share of pixel (u, v): 1 inside, 0 outside, linear over the pixel across its edge.
double Coverage(double u, double v, const Eigen::Vector2d& centre, double radius) {
  const double d = std::hypot(u - centre.x(), v - centre.y());
  return std::clamp(radius + 0.5 - d, 0.0, 1.0);
}

}  // namespace

LensFlare::LensFlare(const Camera& camera, const Eigen::Vector3d& sun_in_tanker, const Eigen::Vector3d& sun_light,
                     const std::vector<FlareGhost>& ghosts)
    : width_(camera.intrinsics.width_px), height_(camera.intrinsics.height_px) {
  if (ghosts.empty()) throw Error("LensFlare: no ghosts");
  image_.assign(static_cast<size_t>(width_) * height_ * 3, 0.0f);
  const Eigen::Vector3d sun = camera.tanker_from_camera.linear().transpose() * sun_in_tanker.normalized();
  const double aperture = sun.z();  // the cosine of the sun's angle to the optical axis
  if (aperture <= 0.0) return;
  const Intrinsics& k = camera.intrinsics;
  const Eigen::Vector2d centre(k.cx_px, k.cy_px);
  const Eigen::Vector2d sun_px(k.cx_px + k.fx_px * sun.x() / sun.z(), k.cy_px + k.fy_px * sun.y() / sun.z());
  const Eigen::Vector3d irradiance = std::numbers::pi * aperture * sun_light;
  for (const FlareGhost& ghost : ghosts) {
    const Eigen::Vector2d at = centre + ghost.position * (sun_px - centre);
    centres_px_.push_back(at);
    const double reach = ghost.radius_px + 1.0;
    // The disc's whole footprint, in the image or not: its solid angle, so
    // that the part beyond the image is lost rather than crowded in.
    const int u0 = static_cast<int>(std::floor(at.x() - reach)), u1 = static_cast<int>(std::ceil(at.x() + reach));
    const int v0 = static_cast<int>(std::floor(at.y() - reach)), v1 = static_cast<int>(std::ceil(at.y() + reach));
    double solid_angle = 0.0;
    for (int v = v0; v <= v1; ++v) {
      for (int u = u0; u <= u1; ++u) solid_angle += Coverage(u, v, at, ghost.radius_px) * PixelSolidAngle(k, u, v);
    }
    const Eigen::Vector3d radiance = ghost.fraction * irradiance / solid_angle;
    for (int v = std::max(v0, 0); v <= std::min(v1, height_ - 1); ++v) {
      for (int u = std::max(u0, 0); u <= std::min(u1, width_ - 1); ++u) {
        const double c = Coverage(u, v, at, ghost.radius_px);
        if (c == 0.0) continue;
        float* out = &image_[(static_cast<size_t>(v) * width_ + u) * 3];
        for (int ch = 0; ch < 3; ++ch) out[ch] += static_cast<float>(c * radiance[ch]);
      }
    }
  }
}

LinearImage LensFlare::Apply(const LinearImage& radiance, const SensorExposure&) const {
  if (radiance.width != width_ || radiance.height != height_) {
    throw Error("LensFlare: a " + std::to_string(radiance.width) + " x " + std::to_string(radiance.height) +
                " image for a " + std::to_string(width_) + " x " + std::to_string(height_) + " camera");
  }
  LinearImage out = radiance;
  for (size_t i = 0; i < out.rgb.size(); ++i) out.rgb[i] += image_[i];
  return out;
}

}  // namespace aar
