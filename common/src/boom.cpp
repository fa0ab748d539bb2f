#include "aar/boom.h"

#include <cmath>
#include <numbers>

#include "aar/error.h"
#include "aar/text.h"

namespace aar {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

void CheckRange(const std::string& where, const char* name, double value, double low, double high) {
  if (!(value >= low && value <= high)) {
    throw Error(where + ": " + name + " " + FormatFixed(value, 4) + " must be in [" + FormatFixed(low, 1) + ", " +
                FormatFixed(high, 1) + "]");
  }
}

}  // namespace

void BoomPose::Check(const std::string& where) const {
  CheckRange(where, "boom_pitch_deg", pitch_deg, 0.0, 45.0);
  CheckRange(where, "boom_roll_deg", roll_deg, -25.0, 25.0);
  CheckRange(where, "boom_extension_m", extension_m, 0.0, kBoomTelescopeM);
}

Eigen::Isometry3d TankerFromBoom(const BoomPose& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = kBoomHingeInTanker;
  t.linear() = (Eigen::AngleAxisd(pose.roll_deg * kDegToRad, Eigen::Vector3d::UnitX()) *
                Eigen::AngleAxisd(-pose.pitch_deg * kDegToRad, Eigen::Vector3d::UnitY()))
                   .toRotationMatrix();
  return t;
}

Eigen::Isometry3d TankerFromBoomTube(const BoomPose& pose) {
  return TankerFromBoom(pose) * Eigen::Translation3d(-pose.extension_m, 0.0, 0.0);
}

Eigen::Vector3d BoomNozzleInTanker(const BoomPose& pose) {
  return TankerFromBoomTube(pose) * Eigen::Vector3d(-kBoomNozzleTipM, 0.0, 0.0);
}

}  // namespace aar
