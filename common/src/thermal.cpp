#include "aar/thermal.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "aar/error.h"
#include "aar/json_number.h"

namespace aar {
namespace {

// CODATA 2018, exact by the SI's definitions.
constexpr double kPlanck = 6.62607015e-34;      // J s
constexpr double kLight = 299792458.0;          // m / s
constexpr double kBoltzmann = 1.380649e-23;     // J / K
constexpr double kMinK = 20.0, kMaxK = 2000.0;  // the table's range
constexpr double kStepK = 0.05;
constexpr int kTableIntervals = 200;  // Simpson's rule per entry: 1e-9 of the radiance over a 1 um or wider band

std::string Text(double value) {
  std::ostringstream o;
  o << value;
  return o.str();
}

double Number(const nlohmann::json& j, const char* key, const std::string& where) {
  const nlohmann::json& v = j.at(key);
  if (!v.is_number() || !std::isfinite(v.get<double>())) {
    throw Error(where + ": lwir." + key + " must be a finite number, not " + v.dump());
  }
  return v.get<double>();
}

// Planck's spectral radiance per metre of wavelength [W m^-2 sr^-1 m^-1].
double SpectralRadiance(double wavelength_m, double temperature_k) {
  const double x = kPlanck * kLight / (wavelength_m * kBoltzmann * temperature_k);
  return 2.0 * kPlanck * kLight * kLight / std::pow(wavelength_m, 5.0) / std::expm1(x);
}

}  // namespace

void ThermalCamera::Check(const std::string& where) const {
  const std::string at = where + ": lwir.";
  if (!(band_min_um >= 1.0 && band_max_um <= 30.0 && band_max_um - band_min_um >= 0.1)) {
    throw Error(at + "band_um [" + Text(band_min_um) + ", " + Text(band_max_um) +
                "] must lie in [1, 30] um and be at least 0.1 um wide");
  }
  if (!(netd_mk >= 0.0 && netd_mk <= 10000.0)) throw Error(at + "netd_mk " + Text(netd_mk) + " must be in [0, 10000]");
  if (!(nonuniformity_mk >= 0.0 && nonuniformity_mk <= 10000.0)) {
    throw Error(at + "nonuniformity_mk " + Text(nonuniformity_mk) + " must be in [0, 10000]");
  }
}

ThermalCamera ThermalFromJson(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object()) throw Error(where + ": lwir must be an object");
  static const std::set<std::string> known = {"seed", "band_um", "netd_mk", "nonuniformity_mk"};
  for (const auto& item : j.items()) {
    if (!known.contains(item.key())) {
      throw Error(where + ": lwir." + item.key() + " is not a field of the LWIR camera (docs/dataset-format.md)");
    }
  }
  ThermalCamera c;
  if (j.contains("seed"))
    c.seed = static_cast<uint64_t>(JsonInteger(j.at("seed"), 0, 1LL << 53, where + ": lwir.seed"));
  if (j.contains("band_um")) {
    const nlohmann::json& band = j.at("band_um");
    if (!band.is_array() || band.size() != 2 || !band[0].is_number() || !band[1].is_number()) {
      throw Error(where + ": lwir.band_um must be [short, long] in um");
    }
    c.band_min_um = band[0].get<double>();
    c.band_max_um = band[1].get<double>();
  }
  if (j.contains("netd_mk")) c.netd_mk = Number(j, "netd_mk", where);
  if (j.contains("nonuniformity_mk")) c.nonuniformity_mk = Number(j, "nonuniformity_mk", where);
  c.Check(where);
  return c;
}

nlohmann::json ThermalToJson(const ThermalCamera& c) {
  return {{"seed", c.seed},
          {"band_um", {c.band_min_um, c.band_max_um}},
          {"netd_mk", c.netd_mk},
          {"nonuniformity_mk", c.nonuniformity_mk}};
}

double BandRadiance(double temperature_k, double min_um, double max_um, int intervals) {
  if (intervals < 2 || intervals % 2 != 0)
    throw Error("BandRadiance: Simpson's rule needs an even number of intervals");
  const double a = min_um * 1e-6, b = max_um * 1e-6, h = (b - a) / intervals;
  double sum = SpectralRadiance(a, temperature_k) + SpectralRadiance(b, temperature_k);
  for (int i = 1; i < intervals; ++i) sum += (i % 2 == 1 ? 4.0 : 2.0) * SpectralRadiance(a + i * h, temperature_k);
  return sum * h / 3.0;
}

BandRadianceTable::BandRadianceTable(double min_um, double max_um) {
  const int n = static_cast<int>(std::lround((kMaxK - kMinK) / kStepK)) + 1;
  radiance_.resize(n);
  for (int i = 0; i < n; ++i) radiance_[i] = BandRadiance(kMinK + i * kStepK, min_um, max_um, kTableIntervals);
}

double BandRadianceTable::Radiance(double temperature_k) const {
  const double x = std::clamp((temperature_k - kMinK) / kStepK, 0.0, static_cast<double>(radiance_.size() - 1));
  const size_t i = std::min(static_cast<size_t>(x), radiance_.size() - 2);
  const double f = x - static_cast<double>(i);
  return radiance_[i] + f * (radiance_[i + 1] - radiance_[i]);
}

double BandRadianceTable::BrightnessTemperature(double radiance) const {
  if (radiance <= radiance_.front()) return kMinK;
  if (radiance >= radiance_.back()) return kMaxK;
  const size_t i =
      static_cast<size_t>(std::upper_bound(radiance_.begin(), radiance_.end(), radiance) - radiance_.begin()) - 1;
  const double f = (radiance - radiance_[i]) / (radiance_[i + 1] - radiance_[i]);
  return kMinK + (static_cast<double>(i) + f) * kStepK;
}

double BandRadianceTable::Slope(double temperature_k) const {
  return Radiance(temperature_k + 0.5) - Radiance(temperature_k - 0.5);  // over 1 K
}

}  // namespace aar
