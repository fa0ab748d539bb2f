#include "aar/renderer/camera_exposure.h"

#include <cmath>

namespace aar {

CameraExposure::CameraExposure(double exposure_ev, double render_scale)
    : factor_(static_cast<float>(std::exp2(exposure_ev) / render_scale)) {}

LinearImage CameraExposure::Apply(const LinearImage& radiance, const SensorExposure&) const {
  LinearImage out = radiance;
  for (float& v : out.rgb) v *= factor_;
  return out;
}

}  // namespace aar
