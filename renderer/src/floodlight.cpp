#include "aar/renderer/floodlight.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "aar/error.h"
#include "aar/text.h"

namespace aar {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

}  // namespace

void FloodlightOptions::Check() const {
  if (!(illuminance_lx >= 0.1 && illuminance_lx <= 10000.0)) {
    throw Error("--floodlight " + FormatFixed(illuminance_lx, 3) + ": expected 0.1 to 10000 lx at the aim point");
  }
  if (!(beam_sigma_deg >= 1.0 && beam_sigma_deg <= 60.0)) {
    throw Error("--floodlight-beam " + FormatFixed(beam_sigma_deg, 3) + ": expected 1 to 60 deg");
  }
}

double Floodlight::IlluminanceAt(const Eigen::Vector3d& point, const Eigen::Vector3d& normal) const {
  const Eigen::Vector3d to_light = position_in_tanker - point;
  const double d2 = to_light.squaredNorm();
  const Eigen::Vector3d l = to_light / std::sqrt(d2);
  const double off_axis = std::acos(std::clamp(-l.dot(axis_in_tanker), -1.0, 1.0));
  const double intensity = intensity_cd * std::exp(-0.5 * off_axis * off_axis / (sigma_rad * sigma_rad));
  return intensity * std::max(normal.dot(l), 0.0) / d2;
}

nlohmann::json Floodlight::Json() const {
  return {{"position_in_tanker_m", {position_in_tanker.x(), position_in_tanker.y(), position_in_tanker.z()}},
          {"axis_in_tanker", {axis_in_tanker.x(), axis_in_tanker.y(), axis_in_tanker.z()}},
          {"intensity_cd", intensity_cd},
          {"beam_sigma_deg", sigma_rad / kDeg},
          {"model",
           "white point light between the cameras aimed at the path's nearest receiver position; intensity_cd x "
           "exp(-angle^2 / (2 sigma^2)) off the axis; diffuse and (pbr) specular; casts no shadow"}};
}

Floodlight MakeFloodlight(const FloodlightOptions& options, const StereoRig& rig,
                          const std::vector<Eigen::Vector3d>& receiver_positions_in_tanker) {
  options.Check();
  if (receiver_positions_in_tanker.empty()) throw Error("--floodlight: no receiver position to aim at");
  Floodlight f;
  f.position_in_tanker = 0.5 * (rig.left.tanker_from_camera.translation() + rig.right.tanker_from_camera.translation());
  Eigen::Vector3d aim = receiver_positions_in_tanker.front();
  for (const Eigen::Vector3d& p : receiver_positions_in_tanker) {
    if ((p - f.position_in_tanker).squaredNorm() < (aim - f.position_in_tanker).squaredNorm()) aim = p;
  }
  const double distance_m = (aim - f.position_in_tanker).norm();
  if (distance_m < 1e-6) throw Error("--floodlight: the receiver's position is at the light");
  f.axis_in_tanker = (aim - f.position_in_tanker) / distance_m;
  f.intensity_cd = options.illuminance_lx * distance_m * distance_m;
  f.sigma_rad = options.beam_sigma_deg * kDeg;
  return f;
}

}  // namespace aar
