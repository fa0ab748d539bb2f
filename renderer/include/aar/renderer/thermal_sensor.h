#pragma once
// The LWIR camera's detector (docs/rendering.md, "Thermal camera"): the
// rendered band radiance plus its temporal noise (NETD) and its fixed
// pattern, turned into each pixel's brightness temperature, which the
// encoder writes as a radiometric 16-bit image (0.01 K per count). Pure CPU.

#include <memory>

#include "aar/renderer/thermal_scene.h"
#include "aar/renderer/view_effect.h"

namespace aar {

class ThermalSensor : public ViewEffect {
 public:
  /// `scene`: the band's radiometry, the radiance unit and the camera's noise.
  explicit ThermalSensor(std::shared_ptr<const ThermalScene> scene);

  /// Every channel of the result is the pixel's brightness temperature [K]:
  /// B^-1(L + NETD B'(300 K) n + nonuniformity B'(300 K) m), L the
  /// rendered radiance (its first channel, in the scene's unit), n a
  /// standard normal of (seed, exposure, pixel), m one of (seed, camera, pixel).
  LinearImage Apply(const LinearImage& radiance, const SensorExposure& exposure) const override;

  /// The noise's standard deviations as radiances [W m^-2 sr^-1].
  double temporal_sigma() const { return temporal_sigma_; }
  double fixed_sigma() const { return fixed_sigma_; }

 private:
  std::shared_ptr<const ThermalScene> scene_;
  double temporal_sigma_ = 0.0, fixed_sigma_ = 0.0;
};

}  // namespace aar
