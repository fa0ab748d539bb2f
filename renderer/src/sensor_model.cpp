#include "aar/renderer/sensor_model.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "aar/renderer/bayer.h"
#include "aar/renderer/charge_spill.h"
#include "aar/renderer/counter_noise.h"
#include "aar/renderer/optical_blur.h"

namespace aar {
namespace {

// Streams of the counter-based generator: the fixed pattern (per camera) and
// the temporal noise (per exposure) never share numbers.
constexpr uint64_t kFixedPatternStream = 0x46504eULL;  // "FPN"
constexpr uint64_t kTemporalStream = 0x54454d50ULL;    // "TEMP"

// The photon-transfer model of one sample (EMVA 1288, release 3.1, section 2).
class PhotonTransfer {
 public:
  PhotonTransfer(const SensorParams& sensor, const SensorExposure& exposure)
      : s_(sensor),
        gain_(sensor.GainDnPerElectron()),
        max_dn_(std::ldexp(1.0, sensor.adc_bits) - 1.0),
        to_radiance_(1.0 / (gain_ * sensor.exposure_e)),
        temporal_key_(
            Mix(Mix(Mix(Mix(sensor.seed, kTemporalStream), exposure.sequence), exposure.index), exposure.camera)) {}

  // Mean photo-electrons of a value, with its pixel's gain (PRNU).
  double MeanElectrons(float radiance, double pixel_gain) const {
    return std::max(0.0, static_cast<double>(radiance) * s_.exposure_e * pixel_gain);
  }

  // `sample`: the value's place in the image (pixel * 3 + channel, or the
  // pixel under a mosaic); `photo_mean` its mean photo-electrons (after
  // the smear and blooming), `dark_e` its fixed dark offset.
  float Measure(double photo_mean, uint64_t sample, double dark_e) const {
    const NormalPair temporal = Normals(Mix(temporal_key_, sample));
    // Shot noise: Poisson, variance = mean, drawn as its Gaussian approximation; clipped at the full well.
    const double photo = std::clamp(photo_mean + std::sqrt(photo_mean) * temporal.first, 0.0, s_.full_well_e);
    // This pixel's dark offset (DSNU) and the read noise.
    const double dark = dark_e + s_.read_noise_e * temporal.second;
    const double dn = std::clamp(std::floor(gain_ * (photo + dark) + s_.black_level_dn + 0.5), 0.0, max_dn_);
    return static_cast<float>((dn - s_.black_level_dn) * to_radiance_);
  }

 private:
  const SensorParams& s_;
  double gain_;         // K [DN/e-]
  double max_dn_;       // the ADC's largest code
  double to_radiance_;  // DN above black -> radiance
  uint64_t temporal_key_;
};

}  // namespace

struct SensorModel::FixedPattern {
  std::vector<double> pixel_gain;  // 1 + PRNU * n1 per sample
  std::vector<double> dark_e;      // DSNU * n2 per sample [e-]
};

SensorModel::SensorModel(SensorParams params) : params_(std::move(params)) {}

SensorModel::~SensorModel() = default;

const SensorModel::FixedPattern& SensorModel::Pattern(uint64_t camera, size_t samples) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::unique_ptr<FixedPattern>& pattern = patterns_[{camera, samples}];
  if (!pattern) {
    pattern = std::make_unique<FixedPattern>();
    pattern->pixel_gain.resize(samples);
    pattern->dark_e.resize(samples);
    const uint64_t key = Mix(Mix(params_.seed, kFixedPatternStream), camera);
    for (size_t i = 0; i < samples; ++i) {
      const NormalPair fixed = Normals(Mix(key, i));
      pattern->pixel_gain[i] = 1.0 + params_.prnu * fixed.first;
      pattern->dark_e[i] = params_.dsnu_e * fixed.second;
    }
  }
  return *pattern;
}

LinearImage SensorModel::Apply(const LinearImage& radiance, const SensorExposure& exposure) const {
  const LinearImage blurred = GaussianBlur(radiance, params_.blur_sigma_px);  // in linear light, before the noise
  const PhotonTransfer transfer(params_, exposure);
  const int width = blurred.width;
  const int height = blurred.height;
  const ChargeSpillOptions spill{params_.full_well_e, params_.blooming, params_.smear};
  if (params_.bayer == BayerPattern::kNone) {
    const FixedPattern& fixed = Pattern(exposure.camera, blurred.rgb.size());
    std::vector<double> electrons(blurred.rgb.size());
    for (size_t i = 0; i < electrons.size(); ++i)
      electrons[i] = transfer.MeanElectrons(blurred.rgb[i], fixed.pixel_gain[i]);
    SpillCharge(electrons, width, height, 3, spill);
    LinearImage out = blurred;
    for (size_t i = 0; i < out.rgb.size(); ++i) out.rgb[i] = transfer.Measure(electrons[i], i, fixed.dark_e[i]);
    return out;
  }
  // RGGB: each pixel measures the one channel its filter passes (ideal filters, no crosstalk).
  const size_t pixels = static_cast<size_t>(width) * height;
  const FixedPattern& fixed = Pattern(exposure.camera, pixels);
  std::vector<double> electrons(pixels);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const size_t pixel = static_cast<size_t>(y) * width + x;
      electrons[pixel] = transfer.MeanElectrons(blurred.rgb[3 * pixel + RggbChannel(y, x)], fixed.pixel_gain[pixel]);
    }
  }
  SpillCharge(electrons, width, height, 1, spill);
  std::vector<float> mosaic(pixels);
  for (size_t pixel = 0; pixel < pixels; ++pixel)
    mosaic[pixel] = transfer.Measure(electrons[pixel], pixel, fixed.dark_e[pixel]);
  return DemosaicRggbBilinear(mosaic, width, height);
}

LinearImage ApplySensorModel(const LinearImage& radiance, const SensorParams& sensor, const SensorExposure& exposure) {
  return SensorModel(sensor).Apply(radiance, exposure);
}

}  // namespace aar
