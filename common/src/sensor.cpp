#include "aar/sensor.h"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "aar/error.h"
#include "aar/json_number.h"

namespace aar {
namespace {

double Number(const nlohmann::json& j, const char* key, const std::string& where) {
  const nlohmann::json& v = j.at(key);
  if (!v.is_number()) throw Error(where + ": sensor." + key + " must be a number, not " + v.dump());
  const double value = v.get<double>();
  if (!std::isfinite(value)) throw Error(where + ": sensor." + key + " is not finite");
  return value;
}

// A value as a message shows it: shortest form, "-1" rather than "-1.000000".
std::string Text(double value) {
  std::ostringstream o;
  o << value;
  return o.str();
}

}  // namespace

double SensorParams::GainDnPerElectron() const {
  return (std::ldexp(1.0, adc_bits) - 1.0 - black_level_dn) / full_well_e;
}

void SensorParams::Check(const std::string& where) const {
  const std::string at = where + ": sensor.";
  // Electron counts are single-precision floats in the sensor model; 10^9 e- is a
  // thousand times the largest full well of a real sensor and far from overflow.
  constexpr double kMaxElectrons = 1e9;
  if (!(exposure_e > 0.0 && exposure_e <= kMaxElectrons)) {
    throw Error(at + "exposure_e " + Text(exposure_e) + " must be in (0, 1e9] [e- at radiance 1]");
  }
  if (!(full_well_e >= 1.0 && full_well_e <= kMaxElectrons)) {
    throw Error(at + "full_well_e " + Text(full_well_e) + " must be in [1, 1e9] [e-]");
  }
  if (!(read_noise_e >= 0.0 && read_noise_e <= kMaxElectrons)) {
    throw Error(at + "read_noise_e " + Text(read_noise_e) + " must be in [0, 1e9] [e-]");
  }
  if (!(prnu >= 0.0 && prnu <= 0.5)) throw Error(at + "prnu " + Text(prnu) + " must be in [0, 0.5]");
  if (!(dsnu_e >= 0.0 && dsnu_e <= kMaxElectrons)) {
    throw Error(at + "dsnu_e " + Text(dsnu_e) + " must be in [0, 1e9] [e-]");
  }
  if (adc_bits < 8 || adc_bits > 16) throw Error(at + "adc_bits " + std::to_string(adc_bits) + " must be 8 to 16");
  if (black_level_dn < 0 || std::ldexp(1.0, adc_bits) - 1.0 - black_level_dn < 1.0) {
    throw Error(at + "black_level_dn " + std::to_string(black_level_dn) + " must be in [0, 2^adc_bits - 2]");
  }
  if (!(blur_sigma_px >= 0.0 && blur_sigma_px <= 10.0)) {
    throw Error(at + "blur_sigma_px " + Text(blur_sigma_px) + " must be in [0, 10] [px]");
  }
  if (!(readout_ms >= 0.0 && readout_ms <= 100.0)) {
    throw Error(at + "readout_ms " + Text(readout_ms) + " must be in [0, 100] [ms] (0: a global shutter)");
  }
  if (!(glare_fraction >= 0.0 && glare_fraction <= 0.2)) {
    throw Error(at + "glare_fraction " + Text(glare_fraction) + " must be in [0, 0.2] (0: no glare)");
  }
  if (!(glare_core_deg >= 0.01 && glare_core_deg <= 10.0)) {
    throw Error(at + "glare_core_deg " + Text(glare_core_deg) + " must be in [0.01, 10] [deg]");
  }
}

SensorParams SensorFromJson(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object()) throw Error(where + ": sensor must be an object");
  static const std::set<std::string> known = {
      "seed",           "exposure_e",    "full_well_e", "read_noise_e", "prnu",           "dsnu_e",        "adc_bits",
      "black_level_dn", "blur_sigma_px", "bayer",       "readout_ms",   "glare_fraction", "glare_core_deg"};
  for (const auto& item : j.items()) {
    if (!known.contains(item.key())) {
      throw Error(where + ": sensor." + item.key() + " is not a sensor field (docs/dataset-format.md)");
    }
  }
  SensorParams s;
  if (j.contains("seed")) {
    s.seed = static_cast<uint64_t>(
        JsonInteger(j.at("seed"), 0, std::numeric_limits<long long>::max(), where + ": sensor.seed"));
  }
  if (j.contains("exposure_e")) s.exposure_e = Number(j, "exposure_e", where);
  if (j.contains("full_well_e")) s.full_well_e = Number(j, "full_well_e", where);
  if (j.contains("read_noise_e")) s.read_noise_e = Number(j, "read_noise_e", where);
  if (j.contains("prnu")) s.prnu = Number(j, "prnu", where);
  if (j.contains("dsnu_e")) s.dsnu_e = Number(j, "dsnu_e", where);
  if (j.contains("adc_bits")) {
    s.adc_bits = static_cast<int>(JsonInteger(j.at("adc_bits"), 8, 16, where + ": sensor.adc_bits"));
  }
  if (j.contains("black_level_dn")) {
    s.black_level_dn =
        static_cast<int>(JsonInteger(j.at("black_level_dn"), 0, 65534, where + ": sensor.black_level_dn"));
  }
  if (j.contains("blur_sigma_px")) s.blur_sigma_px = Number(j, "blur_sigma_px", where);
  if (j.contains("readout_ms")) s.readout_ms = Number(j, "readout_ms", where);
  if (j.contains("glare_fraction")) s.glare_fraction = Number(j, "glare_fraction", where);
  if (j.contains("glare_core_deg")) s.glare_core_deg = Number(j, "glare_core_deg", where);
  if (j.contains("bayer")) {
    const nlohmann::json& b = j.at("bayer");
    if (b == "none") {
      s.bayer = BayerPattern::kNone;
    } else if (b == "rggb") {
      s.bayer = BayerPattern::kRggb;
    } else {
      throw Error(where + ": sensor.bayer " + b.dump() + " must be \"none\" or \"rggb\"");
    }
  }
  s.Check(where);
  return s;
}

nlohmann::json SensorToJson(const SensorParams& s) {
  nlohmann::json j = nlohmann::json::object({{"seed", s.seed},
                                             {"exposure_e", s.exposure_e},
                                             {"full_well_e", s.full_well_e},
                                             {"read_noise_e", s.read_noise_e},
                                             {"prnu", s.prnu},
                                             {"dsnu_e", s.dsnu_e},
                                             {"adc_bits", s.adc_bits},
                                             {"black_level_dn", s.black_level_dn},
                                             {"blur_sigma_px", s.blur_sigma_px},
                                             {"bayer", s.bayer == BayerPattern::kRggb ? "rggb" : "none"}});
  if (s.readout_ms > 0.0) j["readout_ms"] = s.readout_ms;
  if (s.glare_fraction > 0.0) {
    j["glare_fraction"] = s.glare_fraction;
    j["glare_core_deg"] = s.glare_core_deg;
  }
  return j;
}

}  // namespace aar
