#include "aar/propeller.h"

#include <cmath>
#include <numbers>

namespace aar {

double PropellerAngleDeg(int i, double rpm, double time_s) {
  const double turns = rpm / 60.0 * time_s;
  const double fraction = turns - std::floor(turns);
  const double angle = std::fmod(kPropellerPhaseDeg.at(static_cast<size_t>(i)) + 360.0 * fraction, 360.0);
  return angle < 0.0 ? angle + 360.0 : angle;
}

Eigen::Isometry3d ReceiverFromPropeller(int i, double rpm, double time_s) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = kPropellerHubsInReceiver.at(static_cast<size_t>(i));
  t.linear() = Eigen::AngleAxisd(PropellerAngleDeg(i, rpm, time_s) * std::numbers::pi / 180.0, Eigen::Vector3d::UnitX())
                   .toRotationMatrix();
  return t;
}

}  // namespace aar
