#include "aar/renderer/thermal_scene.h"

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>

#include "aar/error.h"

namespace aar {

void ThermalSceneOptions::Check() const {
  if (!(airspeed_mps >= 0.0 && airspeed_mps <= 400.0)) {
    throw Error("--airspeed " + std::to_string(airspeed_mps) + ": expected 0 to 400 m/s");
  }
  if (!(sky_temperature_k >= 20.0 && sky_temperature_k <= 400.0)) {
    throw Error("--sky-temperature " + std::to_string(sky_temperature_k) + ": expected 20 to 400 K");
  }
  if (!(board_temperature_k >= 100.0 && board_temperature_k <= 1000.0)) {
    throw Error("--board-temperature " + std::to_string(board_temperature_k) + ": expected 100 to 1000 K");
  }
  if (!(nacelle_excess_k >= 0.0 && nacelle_excess_k <= 500.0)) {
    throw Error("--nacelle-excess " + std::to_string(nacelle_excess_k) + ": expected 0 to 500 K");
  }
}

double StandardAtmosphereTemperatureK(double altitude_m) {
  if (!(altitude_m >= -500.0 && altitude_m <= 20000.0)) {
    throw Error("the standard atmosphere: altitude " + std::to_string(altitude_m) + " m outside -500 to 20000 m");
  }
  return altitude_m <= 11000.0 ? 288.15 - 0.0065 * altitude_m : 216.65;
}

double RecoveryTemperatureK(double static_temperature_k, double airspeed_mps) {
  constexpr double kRecovery = 0.89, kCp = 1004.5;
  return static_temperature_k + kRecovery * airspeed_mps * airspeed_mps / (2.0 * kCp);
}

double EmissivityOf(const Primitive& primitive) {
  return 0.9 - 0.8 * std::clamp(static_cast<double>(primitive.metallic), 0.0, 1.0);
}

ThermalScene::ThermalScene(const ThermalCamera& camera_in, const ThermalSceneOptions& options_in, double altitude_m)
    : camera(camera_in), options(options_in), table(camera_in.band_min_um, camera_in.band_max_um) {
  options.Check();
  air_k = StandardAtmosphereTemperatureK(altitude_m);
  skin_k = RecoveryTemperatureK(air_k, options.airspeed_mps);
  nacelle_k = skin_k + options.nacelle_excess_k;
  reference_radiance = table.Radiance(300.0);
  sky_radiance = table.Radiance(options.sky_temperature_k) / reference_radiance;
}

double ThermalScene::SurfaceRadiance(double temperature_k, double emissivity) const {
  return emissivity * table.Radiance(temperature_k) / reference_radiance + (1.0 - emissivity) * sky_radiance;
}

namespace {

// The model with every primitive unlit at radiance(primitive), untextured.
template <typename RadianceOf>
SceneModel Emitting(const SceneModel& model, RadianceOf radiance_of) {
  SceneModel out = model;
  out.textures.clear();
  for (Primitive& p : out.primitives) {
    const float radiance = static_cast<float>(radiance_of(p));
    p.base_color_factor = {radiance, radiance, radiance, 1.0f};
    p.texture = -1;
    p.emissive = true;
  }
  return out;
}

}  // namespace

SceneModel ThermalScene::Apply(const SceneModel& model) const {
  return Emitting(model, [&](const Primitive& p) {
    return SurfaceRadiance(p.mesh.rfind("nacelle", 0) == 0 ? nacelle_k : skin_k, EmissivityOf(p));
  });
}

SceneModel ThermalScene::ApplyBoard(const SceneModel& board) const {
  return Emitting(board, [&](const Primitive& p) {
    const std::array<float, 4>& c = p.base_color_factor;
    const double luminance = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    return SurfaceRadiance(options.board_temperature_k, 0.1 + 0.85 * std::clamp(luminance, 0.0, 1.0));
  });
}

nlohmann::json ThermalScene::BoardJson() const {
  return {{"board_temperature_k", options.board_temperature_k},
          {"sky_temperature_k", options.sky_temperature_k},
          {"emissivity",
           "0.1 + 0.85 x the material's luminance (light squares paint, dark squares and backing "
           "polished metal)"},
          {"encoding", "one-channel 16-bit PNG, brightness temperature x 100 (0.01 K per count)"}};
}

nlohmann::json ThermalScene::Json() const {
  return {{"air_temperature_k", air_k},
          {"airspeed_mps", options.airspeed_mps},
          {"skin_temperature_k", skin_k},
          {"nacelle_temperature_k", nacelle_k},
          {"sky_temperature_k", options.sky_temperature_k},
          {"reference_radiance_w_m2_sr", reference_radiance},
          {"emissivity", "0.9 - 0.8 x the material's metallicFactor (paint 0.9, bare metal 0.1)"},
          {"model",
           "air: ISO 2533 at the background's altitude; skins at the recovery temperature T + 0.89 V^2 / (2 x 1004.5); "
           "the receiver's meshes named nacelle* nacelle_excess_k warmer; each surface unlit at e B(T) + (1 - e) "
           "L_sky over the band (Planck, Simpson), the flat sky at sky_temperature_k (thermal_scene.h)"},
          {"encoding", "one-channel 16-bit PNG, brightness temperature x 100 (0.01 K per count)"}};
}

}  // namespace aar
