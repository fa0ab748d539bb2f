#pragma once
// The tanker's flying boom (docs/scenes.md, "Boom"): its
// dimensions, where it is hinged under the tanker's tail, and its pose from
// the boom operator's three controls (flight-path columns boom_pitch_deg,
// boom_roll_deg, boom_extension_m; docs/dataset-format.md).
//
// Boom frame: origin at the hinge; at zero pitch and roll its axes are the
// tanker's (x forward, y left, z up) and the boom lies along -x (aft). The
// telescoping tube frame is the boom frame moved aft along the boom by the
// extension.

#include <Eigen/Geometry>
#include <string>

namespace aar {

/// The boom operator's controls. The defaults are the stowed boom: raised to
/// the tanker's horizontal, centred, retracted (out of the cameras' view).
struct BoomPose {
  double pitch_deg = 0.0;  ///< elevation below the tanker's horizontal, positive down [deg], 0 to 45
  double roll_deg =
      0.0;  ///< swing about the tanker's x axis through the hinge, positive to the left (+y) [deg], -25 to 25
  double extension_m = 0.0;  ///< telescoping tube beyond its retracted position [m], 0 to kBoomTelescopeM

  /// Throws aar::Error, prefixed by `where`, naming the first value outside its range.
  void Check(const std::string& where) const;
};

/// The hinge in the tanker frame [m]: under the tail cone, 2.5 m aft of the
/// cameras and 1.3 m above them (fuselage underside there: z = -1.42).
inline const Eigen::Vector3d kBoomHingeInTanker(-22.5, 0.0, -1.6);

// Dimensions along the boom, metres aft of the hinge (docs/scenes.md gives the sources).
inline constexpr double kBoomFairingLengthM = 3.2;      ///< hinge fairing (pod around the boom root)
inline constexpr double kBoomOuterTubeEndM = 11.0;      ///< end of the fixed outer tube
inline constexpr double kBoomOuterRadiusM = 0.23;       ///< outer tube radius (0.46 m diameter)
inline constexpr double kBoomRuddevatorStationM = 8.4;  ///< ruddevator root leading edge
inline constexpr double kBoomInnerStartM = 7.4;         ///< inner tube start (inside the outer tube), retracted
inline constexpr double kBoomInnerRadiusM = 0.15;       ///< telescoping tube radius
inline constexpr double kBoomNozzleTipM = 13.6;         ///< nozzle tip, retracted
inline constexpr double kBoomTelescopeM = 6.0;          ///< telescoping travel

/// tanker_from_boom = Translation(hinge) * Rx(roll) * Ry(-pitch): pitch about
/// the hinge's lateral axis (inner gimbal), roll about the tanker's x axis
/// (outer gimbal).
Eigen::Isometry3d TankerFromBoom(const BoomPose& pose);

/// tanker_from_boom_tube = tanker_from_boom * Translation(-extension, 0, 0).
Eigen::Isometry3d TankerFromBoomTube(const BoomPose& pose);

/// The nozzle tip in the tanker frame [m].
Eigen::Vector3d BoomNozzleInTanker(const BoomPose& pose);

}  // namespace aar
