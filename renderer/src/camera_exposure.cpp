#include "aar/renderer/camera_exposure.h"

#include <cmath>
#include <string>

#include "aar/error.h"

namespace aar {

CameraExposure::CameraExposure(double exposure_ev, double render_scale)
    : factors_{static_cast<float>(std::exp2(exposure_ev) / render_scale)} {}

CameraExposure::CameraExposure(const std::vector<double>& ev_per_frame, double render_scale) : per_frame_(true) {
  if (ev_per_frame.empty()) throw Error("CameraExposure: no frames");
  for (double ev : ev_per_frame) factors_.push_back(static_cast<float>(std::exp2(ev) / render_scale));
}

LinearImage CameraExposure::Apply(const LinearImage& radiance, const SensorExposure& exposure) const {
  if (per_frame_ && (exposure.sequence != 0 || exposure.index >= factors_.size())) {
    throw Error("CameraExposure: no auto-exposure for " + std::string(exposure.sequence == 0 ? "frame " : "pair ") +
                std::to_string(exposure.index) + " (" + std::to_string(factors_.size()) + " frames)");
  }
  const float factor = per_frame_ ? factors_[exposure.index] : factors_.front();
  LinearImage out = radiance;
  for (float& v : out.rgb) v *= factor;
  return out;
}

}  // namespace aar
