#include "aar/analyzer/propeller_mask.h"

#include <cmath>
#include <numbers>

#include "aar/error.h"
#include "aar/propeller.h"

namespace aar {

void PropellerMaskOptions::Check() const {
  if (!(radial_margin_m >= 0.0 && radial_margin_m <= 2.0))
    throw Error("propeller mask: radial_margin_m must be in [0, 2]");
  if (!(axial_half_width_m > 0.0 && axial_half_width_m <= 3.0))
    throw Error("propeller mask: axial_half_width_m must be in (0, 3]");
  if (!(first_axial_half_width_m > 0.0 && first_axial_half_width_m <= 3.0))
    throw Error("propeller mask: first_axial_half_width_m must be in (0, 3]");
  if (passes < 1 || passes > 10) throw Error("propeller mask: passes must be in [1, 10]");
}

std::vector<Eigen::Vector3d> OutsidePropellerDiscs(const std::vector<Eigen::Vector3d>& sensed_in_tanker,
                                                   const Eigen::Isometry3d& tanker_from_receiver,
                                                   const Eigen::Vector3d& camera_in_tanker,
                                                   const PropellerMaskOptions& options, double axial_half_width_m,
                                                   size_t* removed) {
  const Eigen::Isometry3d receiver_from_tanker = tanker_from_receiver.inverse();
  const Eigen::Vector3d camera = receiver_from_tanker * camera_in_tanker;
  const double radius = 0.5 * kPropellerDiameterM + options.radial_margin_m;
  std::vector<Eigen::Vector3d> kept;
  kept.reserve(sensed_in_tanker.size());
  for (const Eigen::Vector3d& p : sensed_in_tanker) {
    const Eigen::Vector3d q = receiver_from_tanker * p;
    bool inside = false;
    for (const Eigen::Vector3d& hub : kPropellerHubsInReceiver) {
      const Eigen::Vector3d d = q - hub;  // the axis is the receiver's x
      inside = inside || (std::abs(d.x()) <= axial_half_width_m && d.y() * d.y() + d.z() * d.z() <= radius * radius);
      // Behind the disc's plane, seen from the camera on its other side: where the ray crosses the plane.
      const Eigen::Vector3d c = camera - hub;
      if (!inside && c.x() * d.x() < 0.0) {
        const Eigen::Vector3d crossing = c + (d - c) * (c.x() / (c.x() - d.x()));
        inside = crossing.y() * crossing.y() + crossing.z() * crossing.z() <= radius * radius;
      }
    }
    if (!inside) kept.push_back(p);
  }
  if (removed != nullptr) *removed = sensed_in_tanker.size() - kept.size();
  return kept;
}

bool PropellerMaskAgrees(const Eigen::Isometry3d& masked_at, const Eigen::Isometry3d& registered,
                         double axial_half_width_m) {
  // The registered pose seen from the masked one, in the receiver frame, whose x is the discs' axis.
  const Eigen::Isometry3d moved = masked_at.inverse() * registered;
  constexpr int kRimPoints = 16;
  const double radius = 0.5 * kPropellerDiameterM;
  for (const Eigen::Vector3d& hub : kPropellerHubsInReceiver) {
    const Eigen::Vector3d hub_moved = moved * hub - hub;
    if (std::hypot(hub_moved.y(), hub_moved.z()) > radius) return false;
    for (int k = 0; k < kRimPoints; ++k) {
      const double angle = 2.0 * std::numbers::pi * k / kRimPoints;
      const Eigen::Vector3d rim = hub + radius * Eigen::Vector3d(0.0, std::cos(angle), std::sin(angle));
      if (std::abs((moved * rim - rim).x()) > axial_half_width_m) return false;
    }
  }
  return true;
}

}  // namespace aar
