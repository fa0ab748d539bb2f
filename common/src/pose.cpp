#include "aar/pose.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace aar {
namespace {
constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kRadToDeg = 180.0 / std::numbers::pi;
}  // namespace

Eigen::Matrix3d RotationFromRollPitchYaw(double roll_deg, double pitch_deg, double yaw_deg) {
  return (Eigen::AngleAxisd(yaw_deg * kDegToRad, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(pitch_deg * kDegToRad, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll_deg * kDegToRad, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Isometry3d IsometryFromPose(const Pose& pose) {
  Eigen::Isometry3d a_from_b = Eigen::Isometry3d::Identity();
  a_from_b.linear() = RotationFromRollPitchYaw(pose.roll_deg, pose.pitch_deg, pose.yaw_deg);
  a_from_b.translation() = pose.translation_m;
  return a_from_b;
}

Eigen::Quaterniond UnitQuaternion(const Eigen::Matrix3d& rotation) {
  Eigen::Quaterniond q(rotation);
  q.normalize();
  if (q.w() < 0.0) q.coeffs() = -q.coeffs();
  return q;
}

Pose PoseFromIsometry(const Eigen::Isometry3d& a_from_b) {
  // R = Rz(y) Ry(p) Rx(r):  R(2,0) = -sin(p), R(2,1) = cos(p) sin(r),
  // R(2,2) = cos(p) cos(r), R(1,0) = sin(y) cos(p), R(0,0) = cos(y) cos(p).
  const Eigen::Matrix3d r = a_from_b.linear();
  Pose pose;
  pose.translation_m = a_from_b.translation();
  const double sin_pitch = std::clamp(-r(2, 0), -1.0, 1.0);
  pose.pitch_deg = std::asin(sin_pitch) * kRadToDeg;
  if (std::abs(sin_pitch) < 1.0 - 1e-12) {
    pose.roll_deg = std::atan2(r(2, 1), r(2, 2)) * kRadToDeg;
    pose.yaw_deg = std::atan2(r(1, 0), r(0, 0)) * kRadToDeg;
  } else {  // Gimbal lock: put everything in yaw.
    pose.roll_deg = 0.0;
    pose.yaw_deg = std::atan2(-r(0, 1), r(1, 1)) * kRadToDeg;
  }
  pose.roll_deg = WrapDegrees(pose.roll_deg);
  pose.yaw_deg = WrapDegrees(pose.yaw_deg);
  return pose;
}

double WrapDegrees(double angle_deg) {
  double wrapped = std::fmod(angle_deg, 360.0);
  if (wrapped <= -180.0) wrapped += 360.0;
  if (wrapped > 180.0) wrapped -= 360.0;
  return wrapped;
}

Eigen::Matrix3d BodyFromGltf() {
  Eigen::Matrix3d m;
  m << 0, 0, 1,  //
      1, 0, 0,   //
      0, 1, 0;
  return m;
}

}  // namespace aar
