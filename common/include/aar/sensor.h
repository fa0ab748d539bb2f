#pragma once
// The image sensor of a rig (optional "sensor" block, schema aar-rig/3;
// docs/rendering.md, "Sensor model"): a photon-transfer model after EMVA
// 1288 (exposure, shot noise, read noise, fixed-pattern noise, full well,
// ADC), an optical blur and an optional Bayer mosaic. The parameters live
// here, beside the rig; the renderer applies them (renderer/sensor_model.h).

#include <cstddef>
#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

namespace aar {

/// One ghost of lens flare (renderer/lens_flare.h): an out-of-focus image
/// of the aperture that light from the sun makes after two reflections
/// between the lens's surfaces, on the line from the image centre through
/// the sun's image.
struct FlareGhost {
  double position = -1.0;   ///< where along that line: centre + position (sun - centre); < 0 across the centre
  double radius_px = 20.0;  ///< the disc's radius [px]
  double fraction = 1e-4;   ///< the share of the sun's light the ghost receives
};

/// Colour filter array in front of the pixels.
enum class BayerPattern {
  kNone,  ///< every pixel measures red, green and blue (a three-sensor camera)
  kRggb,  ///< RGGB mosaic: even rows R G R G ..., odd rows G B G B ...; bilinear demosaicing
};

/// One sensor, shared by both cameras of the rig (each camera has its own
/// fixed pattern, drawn from `seed` and the camera). Defaults are those of a
/// machine-vision CMOS sensor (docs/rendering.md gives the reasoning).
struct SensorParams {
  uint64_t seed = 1;             ///< seed of the temporal and fixed-pattern noise
  double exposure_e = 5000.0;    ///< mean photo-electrons of a pixel at linear radiance 1.0 [e-]
  double full_well_e = 10000.0;  ///< saturation capacity: photo-electrons are clipped here [e-]
  double read_noise_e = 6.0;     ///< temporal dark noise, standard deviation [e-]
  double prnu = 0.01;            ///< photo-response non-uniformity: std. dev. of the per-pixel gain, relative [1]
  double dsnu_e = 2.0;           ///< dark-signal non-uniformity: std. dev. of the per-pixel offset [e-]
  int adc_bits = 12;             ///< ADC resolution [bit], 8 to 16
  int black_level_dn = 64;       ///< ADC offset added to every pixel, so dark noise is not clipped [DN]
  double blur_sigma_px = 0.0;    ///< optical blur: standard deviation of the Gaussian PSF [px]; 0 = none
  BayerPattern bayer = BayerPattern::kNone;  ///< colour filter array
  /// Rolling shutter: time from the first row's exposure to the last row's
  /// [ms], rows read out evenly, top to bottom; 0 = a global shutter (every
  /// row at once). The renderer exposes each row at its own instant
  /// (renderer/rolling_shutter.h).
  double readout_ms = 0.0;
  /// Veiling glare of the sun (renderer/sun_glare.h): the share of the
  /// sun's light the lens scatters over the image, 0 = none, and the core
  /// angle of its spread function G(theta) ~ core / (core^2 + theta^2)^1.5.
  double glare_fraction = 0.0;
  double glare_core_deg = 0.5;
  /// Blooming (renderer/sensor_model.h): the share of the charge beyond a
  /// pixel's full well that spills into its column's neighbours, half up
  /// and half down, filling each to its full well before going on; the
  /// rest the anti-blooming drain takes. 0 = none (a drained CMOS pixel).
  double blooming = 0.0;
  /// Smear: the readout's transfer time over the exposure time; each pixel
  /// gains this times its column's mean photo-electrons (the light that
  /// falls on the column while its charge moves through it). 0 = none.
  double smear = 0.0;
  /// Lens flare's ghosts of the sun (renderer/lens_flare.h), at most
  /// kMaxFlareGhosts; none by default.
  std::vector<FlareGhost> flare_ghosts;
  static constexpr size_t kMaxFlareGhosts = 16;

  /// System gain K [DN/e-]: the full well maps to the ADC's largest code,
  /// (2^adc_bits - 1 - black_level_dn) / full_well_e.
  double GainDnPerElectron() const;
  /// Throws aar::Error "<where>: sensor.<field> ..." for a value out of range.
  void Check(const std::string& where) const;
};

/// Reads a rig's "sensor" object: every field is optional (the defaults
/// above), an unknown field is refused; `where` names the file.
SensorParams SensorFromJson(const nlohmann::json& j, const std::string& where);
/// Every field (JSON object keys are sorted); readout_ms only for a rolling
/// shutter, the glare's fields only with glare, blooming and smear only
/// when not 0, flare_ghosts only when there are any, so a sensor without them keeps the record it always had.
nlohmann::json SensorToJson(const SensorParams& sensor);

}  // namespace aar
