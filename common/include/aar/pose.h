#pragma once
// 6-DOF poses in the project's conventions (docs/frames.md): metres, degrees,
// attitude as roll, pitch, yaw applied ZYX: R = Rz(yaw) * Ry(pitch) * Rx(roll).

#include <Eigen/Geometry>

namespace aar {

struct Pose {
  Eigen::Vector3d translation_m = Eigen::Vector3d::Zero();  ///< x, y, z [m]
  double roll_deg = 0.0;                                    ///< about +x [deg]
  double pitch_deg = 0.0;                                   ///< about +y [deg]
  double yaw_deg = 0.0;                                     ///< about +z [deg]
};

/// Rotation Rz(yaw) * Ry(pitch) * Rx(roll).
Eigen::Matrix3d RotationFromRollPitchYaw(double roll_deg, double pitch_deg, double yaw_deg);

/// The rigid transform a_from_b described by `pose` (pose of b expressed in a).
Eigen::Isometry3d IsometryFromPose(const Pose& pose);

/// The unit quaternion of a rotation matrix, with w >= 0 (one of its two
/// signs, always the same).
Eigen::Quaterniond UnitQuaternion(const Eigen::Matrix3d& rotation);

/// Inverse of IsometryFromPose; pitch in [-90, 90], roll and yaw in (-180, 180].
Pose PoseFromIsometry(const Eigen::Isometry3d& a_from_b);

/// Wraps an angle to (-180, 180].
double WrapDegrees(double angle_deg);

/// body_from_gltf: glTF axes (+Y up, +Z forward, +X left) to body axes
/// (x forward, y left, z up).
Eigen::Matrix3d BodyFromGltf();

}  // namespace aar
