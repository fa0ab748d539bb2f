#include "aar/renderer/thermal_sensor.h"

#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>

#include "aar/renderer/counter_noise.h"

namespace aar {
namespace {

constexpr uint64_t kFixedStream = 0x4c574e55ULL;     // "LWNU"
constexpr uint64_t kTemporalStream = 0x4c575454ULL;  // "LWTT"

// A standard normal from 64 random bits (Box-Muller, the cosine of the pair;
// u1 in (0, 1], so the tails reach 6.7 sigma as Normals' do).
double Normal(uint64_t bits) {
  const double u1 = (static_cast<double>(bits >> 32) + 1.0) * 0x1.0p-32;
  const double u2 = static_cast<double>(bits & 0xFFFFFFFFULL) * 0x1.0p-32;
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

}  // namespace

ThermalSensor::ThermalSensor(std::shared_ptr<const ThermalScene> scene) : scene_(std::move(scene)) {
  const double slope = scene_->table.Slope(300.0);
  temporal_sigma_ = scene_->camera.netd_mk * 1e-3 * slope;
  fixed_sigma_ = scene_->camera.nonuniformity_mk * 1e-3 * slope;
}

LinearImage ThermalSensor::Apply(const LinearImage& radiance, const SensorExposure& exposure) const {
  const uint64_t seed = scene_->camera.seed;
  const uint64_t temporal =
      Mix(Mix(Mix(Mix(seed, kTemporalStream), exposure.sequence), exposure.index), exposure.camera);
  const uint64_t fixed = Mix(Mix(seed, kFixedStream), exposure.camera);
  LinearImage out = radiance;
  const size_t pixels = radiance.rgb.size() / 3;
  for (size_t p = 0; p < pixels; ++p) {
    double l = radiance.rgb[3 * p] * scene_->reference_radiance;
    if (temporal_sigma_ > 0.0) l += temporal_sigma_ * Normal(Mix(temporal, p));
    if (fixed_sigma_ > 0.0) l += fixed_sigma_ * Normal(Mix(fixed, p));
    const float t = static_cast<float>(scene_->table.BrightnessTemperature(l));
    out.rgb[3 * p] = out.rgb[3 * p + 1] = out.rgb[3 * p + 2] = t;
  }
  return out;
}

}  // namespace aar
