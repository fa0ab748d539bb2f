#pragma once
// The camera a shadow map is rendered with (pure maths, no Vulkan;
// docs/rendering.md, "Shadows"): a pinhole camera far out towards the sun,
// looking back at the aircraft it frames, so that the depth it sees along
// its axis tells which surfaces the sun reaches.

#include <Eigen/Geometry>

#include "aar/rig.h"

namespace aar {

/// How far from the framed sphere's centre the sun camera sits [m]. Its rays
/// meet the sun's parallel ones at an angle of at most radius / distance:
/// 12 m / 10 km = 1.2 mrad, so a shadow cast from 20 m away lands within
/// 2.4 cm of where parallel rays put it; the map's depths (float, about 10 km)
/// keep about 1 mm.
inline constexpr double kSunCameraDistanceM = 10000.0;

/// The sun camera for a sphere (`centre_in_tanker`, `radius_m`) and the sun's
/// direction (unit vector towards it, tanker frame): it sits
/// kSunCameraDistanceM from the centre towards the sun, its optical axis at
/// the centre, its x axis along sun x tanker z (tanker y when the sun is
/// overhead), square pixels, the principal point at the image's centre, and
/// the focal length that puts the sphere's outline 2 px inside the image's
/// shorter side.
Camera SunCamera(const Eigen::Vector3d& sun_in_tanker, const Eigen::Vector3d& centre_in_tanker, double radius_m,
                 int width_px, int height_px);

}  // namespace aar
