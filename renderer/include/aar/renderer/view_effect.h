#pragma once
// A post-process of one camera's linear radiance before its encoding
// (docs/rendering.md, "Encoding beside rendering"): the lens's resampling of a pinhole
// render (lens_distortion.h), the image sensor (sensor_model.h). A render
// session lists each camera's effects in order (RenderSession::ViewEffects)
// and the pair writer applies them on its threads, one after the other; the
// truth images never pass through them.

#include <cstdint>

#include "aar/image.h"

namespace aar {

/// Which exposure an image is: the counter an effect's random numbers are
/// drawn from (the sensor's temporal noise depends on all three, its fixed
/// pattern on the camera alone).
struct SensorExposure {
  uint64_t sequence = 0;  ///< 0: flight-path frames, 1: calibration pairs
  uint64_t index = 0;     ///< frame or calibration-pair index
  uint64_t camera = 0;    ///< 0: left, 1: right
};

class ViewEffect {
 public:
  virtual ~ViewEffect() = default;
  /// `radiance` after the effect; the same bytes for the same input and
  /// exposure, whatever the thread (effects are shared by the writer's threads).
  virtual LinearImage Apply(const LinearImage& radiance, const SensorExposure& exposure) const = 0;
};

}  // namespace aar
