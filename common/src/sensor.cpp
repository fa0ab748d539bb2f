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

std::vector<FlareGhost> GhostsFromJson(const nlohmann::json& j, const std::string& where) {
  if (!j.is_array()) throw Error(where + ": sensor.flare_ghosts must be an array of ghosts");
  std::vector<FlareGhost> ghosts;
  for (size_t i = 0; i < j.size(); ++i) {
    const nlohmann::json& g = j[i];
    const std::string at = where + ": sensor.flare_ghosts[" + std::to_string(i) + "]";
    if (!g.is_object()) throw Error(at + " must be an object");
    for (const auto& item : g.items()) {
      if (item.key() != "position" && item.key() != "radius_px" && item.key() != "fraction") {
        throw Error(at + "." + item.key() + " is not a ghost field (position, radius_px, fraction)");
      }
    }
    FlareGhost ghost;
    for (const char* key : {"position", "radius_px", "fraction"}) {
      if (!g.contains(key)) throw Error(at + " lacks " + key);
      if (!g.at(key).is_number() || !std::isfinite(g.at(key).get<double>())) {
        throw Error(at + "." + key + " must be a finite number, not " + g.at(key).dump());
      }
    }
    ghost.position = g.at("position").get<double>();
    ghost.radius_px = g.at("radius_px").get<double>();
    ghost.fraction = g.at("fraction").get<double>();
    ghosts.push_back(ghost);
  }
  return ghosts;
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
  if (!(blooming >= 0.0 && blooming <= 1.0)) {
    throw Error(at + "blooming " + Text(blooming) + " must be in [0, 1] (0: the drain takes every excess electron)");
  }
  if (!(smear >= 0.0 && smear <= 0.1)) {
    throw Error(at + "smear " + Text(smear) + " must be in [0, 0.1] (transfer time over exposure time)");
  }
  if (flare_ghosts.size() > kMaxFlareGhosts) {
    throw Error(at + "flare_ghosts: " + std::to_string(flare_ghosts.size()) + " ghosts, at most " +
                std::to_string(kMaxFlareGhosts));
  }
  for (size_t i = 0; i < flare_ghosts.size(); ++i) {
    const FlareGhost& g = flare_ghosts[i];
    const std::string ghost = at + "flare_ghosts[" + std::to_string(i) + "].";
    if (!(g.position >= -2.0 && g.position <= 2.0)) {
      throw Error(ghost + "position " + Text(g.position) + " must be in [-2, 2] (sun - centre)");
    }
    if (!(g.radius_px >= 0.5 && g.radius_px <= 2000.0)) {
      throw Error(ghost + "radius_px " + Text(g.radius_px) + " must be in [0.5, 2000] [px]");
    }
    if (!(g.fraction > 0.0 && g.fraction <= 0.01)) {
      throw Error(ghost + "fraction " + Text(g.fraction) + " must be in (0, 0.01] (of the sun's light)");
    }
  }
}

SensorParams SensorFromJson(const nlohmann::json& j, const std::string& where) {
  if (!j.is_object()) throw Error(where + ": sensor must be an object");
  static const std::set<std::string> known = {"seed",           "exposure_e", "full_well_e", "read_noise_e",
                                              "prnu",           "dsnu_e",     "adc_bits",    "black_level_dn",
                                              "blur_sigma_px",  "bayer",      "readout_ms",  "glare_fraction",
                                              "glare_core_deg", "blooming",   "smear",       "flare_ghosts"};
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
  if (j.contains("blooming")) s.blooming = Number(j, "blooming", where);
  if (j.contains("smear")) s.smear = Number(j, "smear", where);
  if (j.contains("flare_ghosts")) s.flare_ghosts = GhostsFromJson(j.at("flare_ghosts"), where);
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
  if (s.blooming > 0.0) j["blooming"] = s.blooming;
  if (s.smear > 0.0) j["smear"] = s.smear;
  if (!s.flare_ghosts.empty()) {
    nlohmann::json ghosts = nlohmann::json::array();
    for (const FlareGhost& g : s.flare_ghosts) {
      ghosts.push_back({{"position", g.position}, {"radius_px", g.radius_px}, {"fraction", g.fraction}});
    }
    j["flare_ghosts"] = ghosts;
  }
  return j;
}

}  // namespace aar
