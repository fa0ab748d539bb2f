#pragma once
// The camera's exposure (docs/rendering.md, "Exposure and night"): a view
// effect that scales the rendered radiance by 2^EV, the camera's exposure
// (shutter time times aperture area) relative to the one the rig's sensor
// and the ideal sensor's encoding are stated for, and divides out the
// shaders' render scale (daylight.h's RenderScale: kNightRenderScale at
// night). With a sensor, more exposure means more photo-electrons: shot
// noise, read noise and the full well act on what the scene really sends.

#include "aar/renderer/view_effect.h"

namespace aar {

class CameraExposure : public ViewEffect {
 public:
  /// Radiance times 2^exposure_ev / render_scale.
  CameraExposure(double exposure_ev, double render_scale);

  LinearImage Apply(const LinearImage& radiance, const SensorExposure& exposure) const override;
  double factor() const { return factor_; }

 private:
  float factor_ = 1.0f;
};

}  // namespace aar
