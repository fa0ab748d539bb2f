#include "c12_propeller.h"

#include <cmath>
#include <numbers>
#include <string>

#include "aar/error.h"
#include "aar/propeller.h"

namespace aar::scenes {
namespace {

const Material kBlack{"propeller_black", {0.035, 0.035, 0.04, 1.0}, false};
const Material kTip{"propeller_tip", {0.80, 0.78, 0.72, 1.0}, false, 0.0, 0.5};

constexpr double kHubAftOfSpinnerTipM = 0.30;
constexpr double kRootRadiusM = 0.17;  // inside the spinner (radius 0.20 m there)
constexpr double kTipRadiusM = 0.5 * kPropellerDiameterM;
constexpr double kTipPaintM = 0.10;  // painted tip band
// Geometric pitch: the blade angle is atan(pitch / (2 pi r)), 28 deg at 3/4 of the radius,
// a constant-speed propeller's blade angle in cruise.
const double kGeometricPitchM = 2.0 * std::numbers::pi * 0.75 * kTipRadiusM * std::tan(28.0 * std::numbers::pi / 180.0);

// Planform (chord) and thickness over the radius: a broad-chord blade, widest
// near mid-span, rounded at the tip; thickness falls from 14 % of the chord
// at the root to 5 % at the tip.
const Profile kChord({kRootRadiusM, 0.20, 0.35, 0.70, 1.00, 1.18, 1.23, kTipRadiusM},
                     {0.0, 0.15, 0.21, 0.23, 0.20, 0.14, 0.09, 0.0});
const Profile kThicknessRatio({kRootRadiusM, 0.40, kTipRadiusM}, {0.14, 0.09, 0.05});

/// A point of blade 0 (along +z) at radius r and section angle phi (0 at the
/// leading edge). The chord lies at the blade angle to the disc plane; the
/// leading edge leads the rotation (-y at blade 0) and faces forward (+x).
Vec3 BladePoint(double r, double phi) {
  const double beta = std::atan(kGeometricPitchM / (2.0 * std::numbers::pi * r));
  const Vec3 chord_dir(std::sin(beta), -std::cos(beta), 0.0);     // trailing edge -> leading edge
  const Vec3 thickness_dir(std::cos(beta), std::sin(beta), 0.0);  // the forward (suction) face's normal
  const double c = kChord(r), t = kThicknessRatio(r) * c;
  return Vec3(0.0, 0.0, r) + 0.5 * c * std::cos(phi) * chord_dir + 0.5 * t * std::sin(phi) * thickness_dir;
}

/// The blade between two radii, as a patch closed around its section.
Patch BladePatch(double r0, double r1, int spans) {
  Patch p;
  p.point = [r0, r1](double u, double v) { return BladePoint(r0 + u * (r1 - r0), -2.0 * std::numbers::pi * v); };
  p.u_samples = UniformSamples(spans);
  p.v_samples = UniformSamples(16);
  p.periodic_v = true;
  return p;
}

/// The mesh of `patch` repeated for every blade, each turned by 360 / blades about +x.
Mesh AllBlades(const Patch& patch) {
  const Mesh one = Tessellate(patch, nullptr);
  Mesh all;
  for (int b = 0; b < kPropellerBlades; ++b) {
    const Eigen::Matrix3d r =
        Eigen::AngleAxisd(2.0 * std::numbers::pi * b / kPropellerBlades, Vec3::UnitX()).toRotationMatrix();
    const auto base = static_cast<std::uint32_t>(all.positions.size());
    for (size_t i = 0; i < one.positions.size(); ++i) {
      all.positions.push_back(r * one.positions[i]);
      all.normals.push_back(r * one.normals[i]);
    }
    for (std::uint32_t i : one.indices) all.indices.push_back(base + i);
  }
  return all;
}

}  // namespace

SceneModel BuildC12Propeller() {
  SceneModel scene;
  scene.name = "c12_propeller";
  scene.materials = {kBlack, kTip};
  const double paint_start = kTipRadiusM - kTipPaintM;
  scene.nodes.push_back(Node{"blades", {Primitive{AllBlades(BladePatch(kRootRadiusM, paint_start, 32)), 0}}});
  scene.nodes.push_back(Node{"tips", {Primitive{AllBlades(BladePatch(paint_start, kTipRadiusM, 6)), 1}}});
  return scene;
}

void CheckPropellerHubs(const C12Airframe& airframe) {
  const Body* nacelles[2] = {&airframe.nacelle_left, &airframe.nacelle_right};
  for (size_t i = 0; i < 2; ++i) {
    const Vec3 hub = nacelles[i]->Point(0.0, 0.0) - Vec3(kHubAftOfSpinnerTipM, 0.0, 0.0);
    if ((hub - kPropellerHubsInReceiver[i]).norm() > 5e-4) {
      throw Error("propeller hub " + std::to_string(i) +
                  " of common/include/aar/propeller.h is not at the nacelle's (" + std::to_string(hub.x()) + ", " +
                  std::to_string(hub.y()) + ", " + std::to_string(hub.z()) + ")");
    }
  }
}

}  // namespace aar::scenes
