#pragma once
// The receiver's exterior lights (docs/rendering.md, "Exposure and night";
// --receiver-lights): the position lights (red on the left wing tip, green
// on the right, white at the tail), the red anti-collision beacons on top of
// the fin and under the belly, and the white strobes at the wing tips, each
// a small sphere of uniform radiance at the airframe's outermost vertex in
// its direction, with the minimum intensities and the flash rates of 14 CFR
// 23.1391-23.1401. Pure CPU: the lights, their sphere models and whether a
// flashing light is on at an instant.

#include <Eigen/Core>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "aar/renderer/scene_model.h"

namespace aar {

struct ReceiverLight {
  std::string name;
  Eigen::Vector3d position_in_receiver = Eigen::Vector3d::Zero();  ///< the sphere's centre [m]
  Eigen::Vector3d color =
      Eigen::Vector3d::Ones();  ///< linear sRGB of unit luminance (0.2126 R + 0.7152 G + 0.0722 B = 1)
  double intensity_cd = 0.0;    ///< luminous intensity while on [cd]
  double radius_m = 0.04;       ///< the sphere's radius [m]
  /// Flashing: on from phase_s for on_s in every period_s; period 0 = steady.
  double period_s = 0.0, on_s = 0.0, phase_s = 0.0;

  /// Whether the light is on at `time_s`.
  bool OnAt(double time_s) const;
  /// The sphere's radiance in the renderer's linear units times `render_scale`:
  /// intensity / (pi r^2) [cd/m^2] x 0.75 pi / 133,800 lx (daylight.h's units).
  Eigen::Vector3d Radiance(double render_scale) const;
};

/// The lights of an airframe (body frame x forward, y left, z up), each
/// sphere just outside the outermost vertex in its direction (its centre one
/// radius beyond it): left tip +y, right tip -y, tail -x, fin top +z, belly -z.
std::vector<ReceiverLight> ReceiverLightsOf(const SceneModel& airframe);

/// A sphere of the light's radius at the origin, one emissive primitive of
/// the light's radiance times `render_scale`.
SceneModel LightSphereModel(const ReceiverLight& light, double render_scale);

/// frames.receiver_lights of the manifest: every light, its place, colour,
/// intensity and flashes, and its mask id.
nlohmann::json ReceiverLightsJson(const std::vector<ReceiverLight>& lights);

}  // namespace aar
