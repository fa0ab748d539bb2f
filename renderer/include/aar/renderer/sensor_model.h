#pragma once
// The image sensor (docs/rendering.md, "Sensor model"): turns a rendered
// linear image (radiance, 1.0 = a white surface in full sun) into what a
// camera with the rig's SensorParams records, in the same linear units, before
// the 8-bit sRGB encoding: optical blur, optional Bayer mosaic, the EMVA 1288
// photon-transfer model (exposure, photon shot noise, read noise, PRNU and
// DSNU fixed patterns, full well, ADC), demosaicing. Pure CPU, deterministic.

#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <utility>

#include "aar/image.h"
#include "aar/renderer/view_effect.h"
#include "aar/sensor.h"

namespace aar {

/// The image `radiance` as the sensor records it, normalised back to
/// radiance: a pixel's value is (DN - black level) / (K * exposure_e), so a
/// noise-free, unsaturated pixel gives back its radiance (up to the ADC's
/// step). Each value's random numbers come from a counter-based hash
/// (splitmix64) of (seed, stream, exposure, sample), never from a sequential
/// generator: the same bytes whatever the thread, shard or order of frames.
LinearImage ApplySensorModel(const LinearImage& radiance, const SensorParams& sensor, const SensorExposure& exposure);

/// The same model for a whole render: each camera's fixed pattern (PRNU and
/// DSNU per sample, two doubles: 38 MB for a 1024 x 768 RGB camera, 13 MB
/// under a mosaic) is drawn once, on first use, and kept, so each exposure
/// draws only its temporal noise. Apply gives the bytes ApplySensorModel
/// gives; safe to call from several threads.
class SensorModel : public ViewEffect {
 public:
  explicit SensorModel(SensorParams params);
  ~SensorModel() override;
  SensorModel(const SensorModel&) = delete;
  SensorModel& operator=(const SensorModel&) = delete;

  LinearImage Apply(const LinearImage& radiance, const SensorExposure& exposure) const override;
  const SensorParams& params() const { return params_; }

 private:
  struct FixedPattern;
  const FixedPattern& Pattern(uint64_t camera, size_t samples) const;

  SensorParams params_;
  mutable std::mutex mutex_;
  mutable std::map<std::pair<uint64_t, size_t>, std::unique_ptr<FixedPattern>> patterns_;
};

}  // namespace aar
