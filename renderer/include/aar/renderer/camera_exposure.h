#pragma once
// The camera's exposure (docs/rendering.md, "Exposure and night"): a view
// effect that scales the rendered radiance by 2^EV, the camera's exposure
// (shutter time times aperture area) relative to the one the rig's sensor
// and the ideal sensor's encoding are stated for, and divides out the
// shaders' render scale (daylight.h's RenderScale: kNightRenderScale at
// night). With a sensor, more exposure means more photo-electrons: shot
// noise, read noise and the full well act on what the scene really sends.

#include <vector>

#include "aar/renderer/view_effect.h"

namespace aar {

class CameraExposure : public ViewEffect {
 public:
  /// Radiance times 2^exposure_ev / render_scale.
  CameraExposure(double exposure_ev, double render_scale);
  /// Auto-exposure (auto_exposure.h): flight-path frame i (SensorExposure's
  /// index) at ev_per_frame[i].
  CameraExposure(const std::vector<double>& ev_per_frame, double render_scale);

  LinearImage Apply(const LinearImage& radiance, const SensorExposure& exposure) const override;
  /// The fixed exposure's factor (auto-exposure: frame 0's).
  double factor() const { return factors_.front(); }

 private:
  std::vector<float> factors_;  // one, or one per flight-path frame
  bool per_frame_ = false;
};

}  // namespace aar
