#pragma once
// The receiver's propellers (docs/scenes.md, "Propellers"):
// where the C-12's two four-blade propellers turn and how fast.
//
// Propeller frame: origin at the hub, in the plane of the blades; its x axis
// is the receiver's (forward, the rotation axis), and at zero angle blade 0
// points along +z. Both propellers turn clockwise seen from behind (the
// PT6A-42's direction on both engines), a positive rotation about +x.

#include <Eigen/Geometry>
#include <array>

namespace aar {

inline constexpr int kPropellerBlades = 4;
inline constexpr double kPropellerDiameterM = 2.5;  ///< tip circle
/// The hubs in the receiver frame [m] (x forward, y left, z up): each
/// nacelle's axis, 0.30 m aft of its spinner tip. scenes/c12.cpp's nacelle
/// geometry gives them; aar-make-scenes refuses to run if they disagree.
inline const std::array<Eigen::Vector3d, 2> kPropellerHubsInReceiver = {
    Eigen::Vector3d(1.9000, 2.6000, -0.1725),   // left engine (+y)
    Eigen::Vector3d(1.9000, -2.6000, -0.1725),  // right engine
};
/// Blade angle of each propeller at time 0 [deg]: the two engines are not
/// synchronized, so their blades do not line up.
inline constexpr std::array<double, 2> kPropellerPhaseDeg = {0.0, 45.0};

/// The blade angle of propeller `i` at `time_s` with the engines at `rpm`,
/// in [0, 360) [deg]: the phase plus rpm / 60 * 360 * time_s, reduced by
/// whole turns before it is scaled, so long times keep their precision.
double PropellerAngleDeg(int i, double rpm, double time_s);

/// receiver_from_propeller = Translation(hub_i) * Rx(PropellerAngleDeg(i, rpm, time_s)).
Eigen::Isometry3d ReceiverFromPropeller(int i, double rpm, double time_s);

}  // namespace aar
