#include "kc46_boom.h"

#include <algorithm>
#include <vector>

#include "aar/boom.h"
#include "shapes.h"

namespace aar::scenes {
namespace {

const Material kBoomGrey{"kc46_boom_grey", {0.55, 0.57, 0.60, 1.0}, false, 0.0, 0.7};
const Material kNozzleDark{"boom_nozzle", {0.30, 0.30, 0.32, 1.0}, false, 1.0, 0.4};

/// A round body along -x from `start_m` to `end_m` aft of the hinge, radius
/// r(s) from the table (s relative to start; 0 at both ends closes it).
Body RoundBody(double start_m, double end_m, const std::vector<double>& s, const std::vector<double>& r) {
  std::vector<double> neg(r.size()), zero(r.size(), 0.0);
  std::transform(r.begin(), r.end(), neg.begin(), [](double v) { return -v; });
  return Body(BodyTables{Profile(s, r), Profile(s, neg), Profile(s, zero), Profile(s, r), 2.0},
              Vec3(-start_m, 0.0, 0.0), end_m - start_m);
}

Body HingeFairing() {
  // A pod around the boom root, deeper than wide; its top is buried in the
  // tail cone above the hinge.
  const double l = kBoomFairingLengthM;
  const std::vector<double> s = {0.0, 0.3, 0.9, 1.6, 2.4, l};
  const std::vector<double> top = {0.0, 0.42, 0.50, 0.48, 0.38, 0.0};
  const std::vector<double> bottom = {0.0, -0.30, -0.40, -0.40, -0.32, 0.0};
  const std::vector<double> half_width = {0.0, 0.30, 0.38, 0.36, 0.30, 0.0};
  std::vector<double> breadth(s.size());
  for (size_t i = 0; i < s.size(); ++i) breadth[i] = 0.5 * (top[i] + bottom[i]);
  return Body(BodyTables{Profile(s, top), Profile(s, bottom), Profile(s, breadth), Profile(s, half_width), 2.0},
              Vec3(0.0, 0.0, 0.0), l);
}

Body OuterTube() {
  const double r = kBoomOuterRadiusM, l = kBoomOuterTubeEndM - 0.3;
  return RoundBody(0.3, kBoomOuterTubeEndM, {0.0, 0.15, 0.6, l - 0.3, l - 0.05, l}, {0.0, 0.8 * r, r, r, r, 0.0});
}

LiftingSurface Ruddevators() {
  // A V of two surfaces, 35 deg above the boom's lateral axis.
  LiftingSurfaceSpec v;
  v.root_leading_edge = Vec3(-kBoomRuddevatorStationM, 0.0, 0.0);
  v.semispan = 2.0;
  v.root_chord = 1.3;
  v.tip_chord = 0.7;
  v.le_sweep_deg = 30.0;
  v.dihedral_deg = 35.0;
  v.root_thickness = 0.12;
  v.tip_thickness = 0.10;
  v.mirrored = true;
  v.cap_m = 0.06;
  return LiftingSurface(v);
}

Body InnerTube() {
  const double r = kBoomInnerRadiusM, start = kBoomInnerStartM, end = kBoomNozzleTipM - 0.55;
  const double l = end - start;
  return RoundBody(start, end, {0.0, 0.05, 0.2, l - 0.1, l - 0.02, l}, {0.0, 0.9 * r, r, r, r, 0.0});
}

Body Nozzle() {
  // Ball joint, then the nozzle tapering to its tip.
  const double start = kBoomNozzleTipM - 0.65, l = 0.65;
  return RoundBody(start, kBoomNozzleTipM, {0.0, 0.05, 0.15, 0.3, 0.5, 0.62, l},
                   {0.0, 0.14, 0.18, 0.15, 0.11, 0.08, 0.0});
}

}  // namespace

SceneModel BuildKc46Boom() {
  SceneModel scene;
  scene.name = "kc46_boom";
  scene.materials.push_back(kBoomGrey);
  auto add = [&scene](const char* name, const Patch& patch) {
    scene.nodes.push_back(Node{name, {Primitive{Tessellate(patch, nullptr), 0}}});
  };
  add("fairing", HingeFairing().MakePatch(24, 24));
  add("outer_tube", OuterTube().MakePatch(40, 24));
  add("ruddevators", Ruddevators().MakePatch(24, 20, 3));
  return scene;
}

SceneModel BuildKc46BoomTube() {
  SceneModel scene;
  scene.name = "kc46_boom_tube";
  scene.materials.push_back(kBoomGrey);
  scene.materials.push_back(kNozzleDark);
  scene.nodes.push_back(Node{"inner_tube", {Primitive{Tessellate(InnerTube().MakePatch(30, 20), nullptr), 0}}});
  scene.nodes.push_back(Node{"nozzle", {Primitive{Tessellate(Nozzle().MakePatch(14, 20), nullptr), 1}}});
  return scene;
}

}  // namespace aar::scenes
