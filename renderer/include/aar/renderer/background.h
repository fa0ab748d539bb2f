#pragma once
// What the cameras see behind the receiver (docs/rendering.md, "Backgrounds"):
// today's uniform sky (the default, the thesis's), or a sky with a horizon at
// the place the tanker's altitude and attitude put it, and below it the ground
// (untextured, or a procedural terrain texture), or the top of a cloud deck,
// faded by aerial perspective. Pure maths here: the `level` frame, the
// horizon, ray intersections with the spherical ground and deck, and the haze;
// shaders/background.frag evaluates the same formulas per pixel.
//
// Frame `level` (local level at the tanker): origin at the tanker origin, z up
// (away from the Earth's centre), x along the tanker's heading projected on the
// horizontal, y left. level_from_tanker = Ry(pitch) Rx(roll) with the tanker's
// roll and pitch in frames.md's conventions (positive pitch: nose down).

#include <Eigen/Geometry>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "aar/rig.h"

namespace aar {

enum class BackgroundKind {
  kFlat,     ///< uniform sky colour everywhere (no horizon, no texture): the thesis's sky
  kSky,      ///< sky gradient above the horizon, untextured hazy ground below it
  kTerrain,  ///< sky gradient, procedural terrain (fields, roads, water, forest) below the horizon
  kClouds,   ///< sky gradient, an overcast cloud deck with textured tops below the horizon
};

/// "flat", "sky", "terrain", "clouds".
const char* BackgroundName(BackgroundKind kind);
/// Inverse of BackgroundName; throws aar::Error listing the names for anything else.
BackgroundKind ParseBackgroundKind(const std::string& name);

/// Object ids of the background in the ground-truth mask (0 stays the sky).
inline constexpr uint8_t kGroundId = 4;
inline constexpr uint8_t kCloudDeckId = 5;

inline constexpr double kEarthRadiusM = 6371000.0;  ///< mean Earth radius, spherical ground [m]

/// Where the sun is, in the tanker's level frame (docs/rendering.md, "The
/// sun"): set directly (--sun-azimuth, --sun-elevation) or from a date, time
/// and place (--sun-time, --latitude, --longitude, --heading; solar_position.h).
struct SunOptions {
  double azimuth_deg = 0.0;     ///< clockwise from the tanker's heading, seen from above [deg], -360 to 360
  double elevation_deg = 45.0;  ///< above the horizon [deg], 0 to 90 (the night has no sun)
  std::string source;           ///< how it was set, recorded in the manifest
};

/// Daylight that follows the sun (daylight.h; docs/rendering.md, "Daylight").
struct DaylightOptions {
  double turbidity = 3.0;  ///< Preetham's atmospheric turbidity, 2 (very clear) to 10 (hazy)
};

/// Night (daylight.h; docs/rendering.md, "Night"): the moon in the sun's
/// place (SunOptions give its direction), its light and the sky it
/// scatters the daylight model's for a sun of the moon's illuminance.
struct NightOptions {
  /// The moon's illuminance outside the atmosphere on a surface facing it
  /// [lx], 0 (no moon) to 1: a full moon about 0.25, a half moon 0.03.
  double moonlight_lx = 0.25;
};

struct BackgroundOptions {
  BackgroundKind kind = BackgroundKind::kFlat;
  double altitude_m = 7000.0;           ///< tanker origin above the ground (ground = sea level) [m], 100 to 20,000
  double cloud_top_m = 3000.0;          ///< cloud deck top above the ground (clouds) [m], 0 to altitude_m - 100
  double tanker_roll_deg = 0.0;         ///< tanker attitude, frames.md conventions [deg], -60 to 60
  double tanker_pitch_deg = 0.0;        ///< positive = nose down [deg], -30 to 30
  double visibility_m = 20000.0;        ///< sea-level meteorological visibility (haze: 2 % contrast) [m], >= 1000
  double haze_scale_height_m = 1500.0;  ///< exponential height scale of the haze [m], 100 to 10,000
  double ground_texel_m = 8.0;          ///< terrain texture resolution on the ground [m per texel], 1 to 64
  double cloud_texel_m = 16.0;          ///< cloud-top texture resolution [m per texel], 1 to 128
  uint32_t seed = 1;                    ///< terrain and cloud layout (the textures are a function of it)
  /// The sun lighting the scene and the sky; none: azimuth 52 deg left of
  /// the heading, elevation 55 deg (SunInLevel), the light every dataset
  /// made without it has.
  std::optional<SunOptions> sun;
  /// The sun's colour and brightness, the sky's radiance and the light on
  /// the aircraft following the sun (and the sun's disc in view); none: the
  /// fixed sky and light of every dataset made without it.
  std::optional<DaylightOptions> daylight;
  /// Night: with daylight (its turbidity), the moon where the sun would be.
  std::optional<NightOptions> night;

  /// Throws aar::Error naming the command-line flag of the first value out of range (or NaN).
  void Check() const;
  bool enabled() const { return kind != BackgroundKind::kFlat; }
};

/// level_from_tanker (rotation only; the tanker origin is the level origin).
Eigen::Matrix3d LevelFromTanker(const BackgroundOptions& options);

/// The sun (unit vector towards it) in the level frame (x along the heading,
/// y left, z up): options.sun's, or without one azimuth 52 deg left of the
/// heading, elevation 55 deg, the direction the aircraft were always lit
/// from (in the tanker frame, for a level tanker).
Eigen::Vector3d SunInLevel(const BackgroundOptions& options);

/// frames.sun of the manifest: the sun's azimuth and elevation, its vector
/// in the level frame and how it was set.
nlohmann::json SunJson(const BackgroundOptions& options);

/// level_from_pixel: the level-frame ray of OpenCV pixel (u, v) is
/// level_from_pixel * (u, v, 1), scaled so that its camera-frame z is 1 (a
/// point t times along it has depth t along the optical axis).
Eigen::Matrix3d LevelFromPixel(const Camera& camera, const BackgroundOptions& options);

/// The camera centre in the level frame, shifted up by the altitude: z is its
/// height above the ground [m].
Eigen::Vector3d CameraAboveGround(const Camera& camera, const BackgroundOptions& options);

/// Depression of the horizon below the horizontal at height h above a sphere of
/// radius R: acos(R / (R + h)) [rad].
double HorizonDipRad(double height_m, double radius_m = kEarthRadiusM);

/// Distance t >= 0 along `direction` (any length; t is in units of it) from a
/// point `height_m` above a sphere of radius `radius_m` to the sphere, when
/// the ray hits it (direction.z() is the level-frame vertical component).
std::optional<double> SphereHitParameter(const Eigen::Vector3d& direction_in_level, double height_m,
                                         double radius_m = kEarthRadiusM);

/// Optical depth of the haze along a straight path of length `length_m` from
/// height z0 to height z1: sigma0 * length * mean(exp(-z / H)), sigma0 = 3.912 /
/// visibility (Koschmieder). Transmittance = exp(-optical depth).
double HazeOpticalDepth(double length_m, double z0_m, double z1_m, const BackgroundOptions& options);

/// The manifest's `frames.background` object: every option, the ids, and the units.
nlohmann::json BackgroundJson(const BackgroundOptions& options);

}  // namespace aar
