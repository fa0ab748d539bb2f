#pragma once
// The tanker's floodlight on the receiver (docs/rendering.md, "Exposure and
// night"; --floodlight): a white point light between the two cameras, aimed
// at the flight path's nearest receiver position, whose intensity falls as
// a Gaussian of the angle off its axis. scene.frag evaluates the same light
// from its specialization constants 13-21. No shadow of its own: from
// beside the cameras the shadows it casts are hidden behind what casts them.

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <vector>

#include "aar/rig.h"

namespace aar {

struct FloodlightOptions {
  double illuminance_lx = 50.0;  ///< on a surface facing the light at its aim point [lx], 0.1 to 10,000
  double beam_sigma_deg = 10.0;  ///< the beam's angular spread, one standard deviation [deg], 1 to 60
  /// Throws aar::Error naming --floodlight or --floodlight-beam for a value out of range.
  void Check() const;
};

struct Floodlight {
  Eigen::Vector3d position_in_tanker = Eigen::Vector3d::Zero();  ///< [m]
  Eigen::Vector3d axis_in_tanker = -Eigen::Vector3d::UnitX();    ///< unit, where the beam points
  double intensity_cd = 0.0;                                     ///< on the axis [cd]
  double sigma_rad = 0.0;

  /// Illuminance [lx] on a surface at `point` with unit normal `normal`
  /// (both tanker frame): I(angle off axis) cos(incidence) / distance^2.
  double IlluminanceAt(const Eigen::Vector3d& point, const Eigen::Vector3d& normal) const;
  /// frames.floodlight of the manifest.
  nlohmann::json Json() const;
};

/// The floodlight at the midpoint of the rig's camera centres, aimed at the
/// nearest of `receiver_positions_in_tanker` (the flight path's), with the
/// intensity that gives options.illuminance_lx there.
Floodlight MakeFloodlight(const FloodlightOptions& options, const StereoRig& rig,
                          const std::vector<Eigen::Vector3d>& receiver_positions_in_tanker);

}  // namespace aar
