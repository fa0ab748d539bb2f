#pragma once
// The sun's veiling glare (docs/rendering.md, "Veiling glare of the sun"):
// light of the sun that the lens scatters (dust, surface roughness,
// reflections between its elements) spreads over the image as a veil that
// falls with the angle to the sun. A view effect on the pinhole render,
// before the lens's resampling and the sensor, where the rig's sensor
// declares a glare_fraction. Pure CPU; the veil depends on the camera and
// the sun alone, so it is computed once per camera and added to every frame.

#include <Eigen/Core>
#include <vector>

#include "aar/renderer/view_effect.h"
#include "aar/rig.h"

namespace aar {

/// The glare spread function [1/sr]: the share of a source's light per
/// steradian at angle `theta_rad` from it, fraction x core / (2 pi (core^2 +
/// theta^2)^1.5), which integrates to `fraction` over the plane around the
/// source (and to within core / pi of it over the sphere).
double GlareSpread(double theta_rad, double fraction, double core_rad);

class SunGlare : public ViewEffect {
 public:
  /// `camera`: the camera the scene is rendered with (its pinhole
  /// intrinsics); `sun_in_tanker`: unit vector to the sun; `sun_light`: the
  /// sun's light at the tanker per channel in the renderer's units (a white
  /// surface facing it has this radiance: its irradiance is pi times it).
  /// The veil is scaled by the cosine of the sun's angle to the optical axis
  /// (the aperture's projected area) and is zero with the sun behind the lens.
  SunGlare(const Camera& camera, const Eigen::Vector3d& sun_in_tanker, const Eigen::Vector3d& sun_light,
           double fraction, double core_deg);

  LinearImage Apply(const LinearImage& radiance, const SensorExposure& exposure) const override;
  /// The veil added to each pixel, linear RGB, row-major (zeros with the sun behind the lens).
  const std::vector<float>& veil() const { return veil_; }

 private:
  int width_ = 0, height_ = 0;
  std::vector<float> veil_;
};

}  // namespace aar
