#include "aar/renderer/background.h"

#include <cmath>
#include <numbers>

#include "aar/error.h"
#include "aar/pose.h"
#include "aar/renderer/daylight.h"

namespace aar {
namespace {

struct KindName {
  BackgroundKind kind;
  const char* name;
};
constexpr KindName kKinds[] = {{BackgroundKind::kFlat, "flat"},
                               {BackgroundKind::kSky, "sky"},
                               {BackgroundKind::kTerrain, "terrain"},
                               {BackgroundKind::kClouds, "clouds"}};

void CheckRange(double value, double lo, double hi, const char* flag, const char* unit) {
  if (!(value >= lo && value <= hi)) {
    throw Error(std::string(flag) + " " + std::to_string(value) + ": expected " + std::to_string(lo) + " to " +
                std::to_string(hi) + " " + unit);
  }
}

}  // namespace

const char* BackgroundName(BackgroundKind kind) {
  for (const KindName& k : kKinds) {
    if (k.kind == kind) return k.name;
  }
  return "?";
}

BackgroundKind ParseBackgroundKind(const std::string& name) {
  for (const KindName& k : kKinds) {
    if (name == k.name) return k.kind;
  }
  throw Error("--background '" + name + "': expected flat, sky, terrain or clouds");
}

void BackgroundOptions::Check() const {
  CheckRange(altitude_m, 100.0, 20000.0, "--altitude", "m");
  if (kind == BackgroundKind::kClouds) CheckRange(cloud_top_m, 0.0, altitude_m - 100.0, "--cloud-top", "m");
  CheckRange(tanker_roll_deg, -60.0, 60.0, "--tanker-roll", "deg");
  CheckRange(tanker_pitch_deg, -30.0, 30.0, "--tanker-pitch", "deg");
  CheckRange(visibility_m, 1000.0, 1e6, "--visibility", "m");
  CheckRange(haze_scale_height_m, 100.0, 10000.0, "haze_scale_height_m", "m");
  CheckRange(ground_texel_m, 1.0, 64.0, "ground_texel_m", "m");
  CheckRange(cloud_texel_m, 1.0, 128.0, "cloud_texel_m", "m");
  if (sun) {
    CheckRange(sun->azimuth_deg, -360.0, 360.0, "--sun-azimuth", "deg");
    CheckRange(sun->elevation_deg, 0.0, 90.0, "--sun-elevation", "deg");
  }
  if (night) {
    if (kind == BackgroundKind::kFlat) {
      throw Error("--night: the flat sky is the thesis's fixed light; use --background sky, terrain or clouds");
    }
    if (!daylight) throw Error("--night: the night's sky is the daylight model's, scaled: set daylight too");
    CheckRange(night->moonlight_lx, 0.0, 1.0, "--moonlight", "lx");
  }
  if (daylight) {
    if (kind == BackgroundKind::kFlat) {
      throw Error("--daylight: the flat sky is the thesis's fixed light; use --background sky, terrain or clouds");
    }
    CheckRange(daylight->turbidity, 2.0, 10.0, "--turbidity", "(Preetham's range)");
  }
}

Eigen::Matrix3d LevelFromTanker(const BackgroundOptions& options) {
  return RotationFromRollPitchYaw(options.tanker_roll_deg, options.tanker_pitch_deg, 0.0);
}

Eigen::Matrix3d LevelFromPixel(const Camera& camera, const BackgroundOptions& options) {
  const Intrinsics& k = camera.intrinsics;
  Eigen::Matrix3d cam_from_pixel;  // K^-1
  cam_from_pixel << 1.0 / k.fx_px, 0.0, -k.cx_px / k.fx_px, 0.0, 1.0 / k.fy_px, -k.cy_px / k.fy_px, 0.0, 0.0, 1.0;
  return LevelFromTanker(options) * camera.tanker_from_camera.linear() * cam_from_pixel;
}

Eigen::Vector3d CameraAboveGround(const Camera& camera, const BackgroundOptions& options) {
  return LevelFromTanker(options) * camera.tanker_from_camera.translation() +
         Eigen::Vector3d(0.0, 0.0, options.altitude_m);
}

Eigen::Vector3d SunInLevel(const BackgroundOptions& options) {
  if (!options.sun) return Eigen::Vector3d(0.35, 0.45, 0.82).normalized();
  constexpr double kDeg = std::numbers::pi / 180.0;
  const double azimuth = options.sun->azimuth_deg * kDeg, elevation = options.sun->elevation_deg * kDeg;
  // Clockwise from the heading seen from above: towards -y (right) for a positive azimuth.
  return {std::cos(elevation) * std::cos(azimuth), -std::cos(elevation) * std::sin(azimuth), std::sin(elevation)};
}

nlohmann::json SunJson(const BackgroundOptions& options) {
  const Eigen::Vector3d sun = SunInLevel(options);
  nlohmann::json j = {{"in_level", {sun.x(), sun.y(), sun.z()}},
                      {"level_frame", "x along the tanker's heading, y left, z up"}};
  if (options.sun) {
    j["azimuth_deg"] = options.sun->azimuth_deg;
    j["elevation_deg"] = options.sun->elevation_deg;
    j["azimuth"] = "clockwise from the tanker's heading, seen from above";
    j["source"] = options.sun->source;
  }
  return j;
}

double HorizonDipRad(double height_m, double radius_m) { return std::acos(radius_m / (radius_m + height_m)); }

std::optional<double> SphereHitParameter(const Eigen::Vector3d& direction_in_level, double height_m, double radius_m) {
  // |p + t d|^2 = R^2 with p = (0, 0, R + h) and unit d: the near root, in the
  // cancellation-free form t = h (2R + h) / ((R + h) (-d_z + sqrt(d_z^2 - sin^2 dip))).
  const double norm = direction_in_level.norm();
  const double dz = direction_in_level.z() / norm;
  const double sin2_dip = height_m * (2.0 * radius_m + height_m) / ((radius_m + height_m) * (radius_m + height_m));
  if (dz >= 0.0 || dz * dz < sin2_dip) return std::nullopt;
  const double t_unit =
      height_m * (2.0 * radius_m + height_m) / ((radius_m + height_m) * (-dz + std::sqrt(dz * dz - sin2_dip)));
  return t_unit / norm;
}

double HazeOpticalDepth(double length_m, double z0_m, double z1_m, const BackgroundOptions& options) {
  const double sigma0 = 3.912 / options.visibility_m;  // Koschmieder: 2 % contrast at the visibility
  const double h = options.haze_scale_height_m;
  const double dz = z0_m - z1_m;
  // Mean of exp(-z / H) for z linear along the path from z0 to z1.
  const double mean_density =
      std::abs(dz) < 1.0 ? std::exp(-0.5 * (z0_m + z1_m) / h) : h * (std::exp(-z1_m / h) - std::exp(-z0_m / h)) / dz;
  return sigma0 * length_m * mean_density;
}

nlohmann::json BackgroundJson(const BackgroundOptions& o) {
  nlohmann::json j = {{"kind", BackgroundName(o.kind)}};
  if (!o.enabled()) {
    j["description"] = "uniform sky colour, no horizon, no texture";
    return j;
  }
  j["altitude_m"] = o.altitude_m;
  j["tanker_roll_deg"] = o.tanker_roll_deg;
  j["tanker_pitch_deg"] = o.tanker_pitch_deg;
  j["earth_radius_m"] = kEarthRadiusM;
  const Eigen::Vector3d sun = SunInLevel(o);
  j["sun_in_level"] = {sun.x(), sun.y(), sun.z()};
  j["visibility_m"] = o.visibility_m;
  j["haze_scale_height_m"] = o.haze_scale_height_m;
  j["seed"] = o.seed;
  if (o.kind == BackgroundKind::kTerrain) j["ground_texel_m"] = o.ground_texel_m;
  if (o.kind == BackgroundKind::kClouds) {
    j["cloud_top_m"] = o.cloud_top_m;
    j["cloud_texel_m"] = o.cloud_texel_m;
  }
  if (o.daylight) j["daylight"] = DaylightJson(o);
  j["mask_ids"] = {{"sky", 0}, {"ground", kGroundId}, {"cloud_deck", kCloudDeckId}};
  j["depth"] = "metres along the optical axis to the ground or deck; 0 = sky (no surface)";
  return j;
}

}  // namespace aar
