#pragma once
// A long-wave infrared (LWIR) camera pair (optional "lwir" block of a rig,
// schema aar-rig/3; docs/rendering.md, "Thermal camera"): its band, its
// noise-equivalent temperature difference and its fixed pattern, and the
// radiometry it rests on, Planck's law integrated over the band. The
// renderer makes radiometric images from it (renderer/thermal_sensor.h).

#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

namespace aar {

struct ThermalCamera {
  uint64_t seed = 1;          ///< seed of the temporal and fixed-pattern noise
  double band_min_um = 8.0;   ///< the band's short edge [um]
  double band_max_um = 14.0;  ///< its long edge [um]
  /// Noise-equivalent temperature difference at a 300 K scene [mK]: the
  /// temporal noise, as a radiance, is NETD x dL/dT at 300 K.
  double netd_mk = 50.0;
  /// The fixed pattern left after the camera's non-uniformity correction,
  /// each pixel's offset as a temperature at 300 K, one standard deviation [mK].
  double nonuniformity_mk = 0.0;

  /// Throws aar::Error naming `where` and the field out of its range.
  void Check(const std::string& where) const;
};

/// The "lwir" block: every field optional with its default; unknown fields refused.
ThermalCamera ThermalFromJson(const nlohmann::json& j, const std::string& where);
nlohmann::json ThermalToJson(const ThermalCamera& camera);

/// A blackbody's radiance in the band [min_um, max_um] at `temperature_k`
/// [W m^-2 sr^-1]: Planck's spectral radiance (CODATA 2018 h, c, k)
/// integrated by Simpson's rule over `intervals` (even) of wavelength.
double BandRadiance(double temperature_k, double min_um, double max_um, int intervals = 1000);

/// Band radiance against temperature, tabulated once for a band, and its
/// inverse, the brightness temperature: 20 to 2,000 K in steps of 0.05 K,
/// linear between (within 1e-3 K of the exact inverse above 100 K).
class BandRadianceTable {
 public:
  BandRadianceTable(double min_um, double max_um);
  double Radiance(double temperature_k) const;
  /// The temperature of the blackbody of this band radiance (clamped to the table's range).
  double BrightnessTemperature(double radiance) const;
  /// dL/dT at `temperature_k` [W m^-2 sr^-1 K^-1].
  double Slope(double temperature_k) const;

 private:
  std::vector<double> radiance_;  // at kMinK + i * kStepK
};

}  // namespace aar
