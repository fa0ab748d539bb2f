#pragma once
// The scene in the long-wave infrared (docs/rendering.md, "Thermal
// camera"): each surface's temperature and emissivity, and the band
// radiance it sends, ε B(T) + (1 - ε) L_sky, rendered as unlit emission
// over a sky of uniform brightness temperature. Pure CPU: the models'
// primitives are made emissive before they reach the renderer.

#include <nlohmann/json_fwd.hpp>

#include "aar/renderer/scene_model.h"
#include "aar/thermal.h"

namespace aar {

struct ThermalSceneOptions {
  /// True airspeed of the tanker and the receiver [m/s]: their skins reach
  /// the adiabatic recovery temperature of the air at it.
  double airspeed_mps = 120.0;
  /// The flat sky's brightness temperature in the band [K].
  double sky_temperature_k = 220.0;
  /// How much warmer than the skin the receiver's engine nacelles are [K]
  /// (the meshes named "nacelle..."; their exhausts are not modelled).
  double nacelle_excess_k = 40.0;
  /// The calibration board's temperature [K]: heated, as infrared
  /// calibration targets are, so that its pattern shows.
  double board_temperature_k = 320.0;
  void Check() const;
};

/// The International Standard Atmosphere's temperature at a geopotential
/// altitude [K]: 288.15 - 0.0065 h to 11 km, 216.65 to 20 km (ISO 2533).
double StandardAtmosphereTemperatureK(double altitude_m);
/// The skin of a body in flight: T + r V^2 / (2 c_p), recovery factor r =
/// 0.89 (a turbulent boundary layer, Pr^(1/3)), c_p = 1004.5 J/(kg K).
double RecoveryTemperatureK(double static_temperature_k, double airspeed_mps);
/// A surface's emissivity from its glTF material: 0.9 painted (metallic
/// 0), 0.1 bare metal (metallic 1), linear between.
double EmissivityOf(const Primitive& primitive);

/// The temperatures of one scene and the band's radiometry. Radiances
/// reach the renderer in units of a 300 K blackbody's band radiance
/// (`reference_radiance`), so that they lie near 1 in half floats.
struct ThermalScene {
  ThermalScene(const ThermalCamera& camera, const ThermalSceneOptions& options, double altitude_m);
  ThermalCamera camera;
  ThermalSceneOptions options;
  double air_k = 0.0, skin_k = 0.0, nacelle_k = 0.0;
  BandRadianceTable table;
  double reference_radiance = 0.0;  ///< the band radiance of a 300 K blackbody [W m^-2 sr^-1]
  double sky_radiance = 0.0;        ///< the sky's, in reference units

  /// In reference units: ε B(T) + (1 - ε) sky.
  double SurfaceRadiance(double temperature_k, double emissivity) const;
  /// The model with every primitive unlit at its surface's radiance (the
  /// receiver's nacelles at nacelle_k, every other surface at skin_k).
  SceneModel Apply(const SceneModel& model) const;
  /// The calibration board at board_temperature_k, its pattern one of
  /// emissivity: e = 0.1 + 0.85 x the material's luminance (its light
  /// squares white paint, 0.865; its dark squares and backing polished
  /// metal, 0.117 and 0.20), so that it shows as it does in the visible.
  SceneModel ApplyBoard(const SceneModel& board) const;
  /// The manifest's frames.thermal: temperatures, radiometry, the model in words.
  nlohmann::json Json() const;
  /// The manifest's calib.thermal: the board's temperature and pattern.
  nlohmann::json BoardJson() const;
};

}  // namespace aar
