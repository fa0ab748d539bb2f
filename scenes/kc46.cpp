#include "kc46.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "aar/error.h"
#include "shapes.h"

namespace aar::scenes {
namespace {

// Published KC-46A / 767-200 figures the model is scaled to.
constexpr double kLength = 50.5;  // m; the origin sits at mid length
constexpr double kHalfLength = 0.5 * kLength;

// Stereo rig of scenes/rig.json: camera centres, optical axis aft and 30 deg
// down, 1024 x 768 px at fx = fy = 900 px.
const std::array<Vec3, 2> kCameraCentres = {Vec3(-20.0, -0.25, -2.9), Vec3(-20.0, 0.25, -2.9)};
const Vec3 kCameraX(0.0, 1.0, 0.0);                         // image right
const Vec3 kCameraY(0.5, 0.0, -0.8660254037844386);         // image down
const Vec3 kCameraZ(-0.8660254037844386, 0.0, -0.5);        // optical axis
constexpr double kTanHalfFovX = 0.5 * 1024 / 900.0 + 0.01;  // with a small margin
constexpr double kTanHalfFovY = 0.5 * 768 / 900.0 + 0.01;
constexpr double kFuselageBottomLimit = -2.6;  // at the rig station
constexpr double kLowestNearRigLimit = -2.8;   // nothing lower within 3 m of the cameras

double XOfStation(double station) { return kHalfLength - station; }

const std::vector<double> kFuselageStations = {0.0,  0.35, 1.0,   2.0,  3.5,  5.0,  7.0,    38.0,
                                               42.0, 44.0, 45.25, 46.5, 48.0, 49.5, kLength};
const Profile kFuselageBottom(kFuselageStations, {-0.60, -1.05, -1.60, -2.05, -2.35, -2.48, -2.50, -2.50, -2.48, -2.40,
                                                  -2.28, -2.00, -1.30, -0.20, 0.90});

Body Fuselage() {
  // 5 m diameter cabin; round nose; tail cone sweeping up from 42 m so the
  // underside stays near the cabin floor line at the camera station.
  const std::vector<double>& s = kFuselageStations;
  BodyTables t{
      Profile(s, {-0.60, -0.20, 0.45, 1.25, 1.95, 2.35, 2.50, 2.50, 2.45, 2.35, 2.25, 2.10, 1.80, 1.35, 0.90}),
      kFuselageBottom,
      Profile(s, {-0.60, -0.60, -0.55, -0.45, -0.30, -0.12, 0.00, 0.00, 0.00, 0.05, 0.10, 0.15, 0.30, 0.55, 0.90}),
      Profile(s, {0.00, 0.50, 1.05, 1.60, 2.10, 2.40, 2.50, 2.50, 2.45, 2.30, 2.12, 1.85, 1.40, 0.75, 0.00}), 2.0};
  return Body(std::move(t), Vec3(XOfStation(0.0), 0.0, 0.0), kLength);
}

Body CameraFairing() {
  // Teardrop under the aft fuselage around the cameras: its top is buried
  // 0.25 m inside the fuselage, its bottom reaches -2.72 m at the rig.
  constexpr double kNose = 42.4, kTail = 47.9;
  const std::vector<double> s = {kNose, 43.0, 43.8, 44.6, 45.25, 46.0, 46.8, 47.4, kTail};
  const std::vector<double> bottom_inner = {0.0, -2.52, -2.64, -2.70, -2.72, -2.70, -2.55, -2.25, 0.0};
  const std::vector<double> half_width = {0.0, 0.30, 0.45, 0.52, 0.55, 0.52, 0.42, 0.25, 0.0};
  std::vector<double> local, top, bottom, breadth;
  for (std::size_t i = 0; i < s.size(); ++i) {
    local.push_back(s[i] - kNose);
    top.push_back(kFuselageBottom(s[i]) + 0.25);
    bottom.push_back(i == 0 || i + 1 == s.size() ? top.back() : bottom_inner[i]);
    breadth.push_back(0.5 * (top.back() + bottom.back()));
  }
  BodyTables t{Profile(local, top), Profile(local, bottom), Profile(local, breadth), Profile(local, half_width), 2.0};
  return Body(std::move(t), Vec3(XOfStation(kNose), 0.0, 0.0), kTail - kNose);
}

Body Engine(double y) {
  // High-bypass nacelle, inlet closed by a shallow dome.
  const std::vector<double> s = {0.0, 0.25, 0.8, 1.8, 3.0, 4.2, 5.2, 5.9, 6.4};
  const std::vector<double> r = {0.0, 0.95, 1.30, 1.37, 1.35, 1.20, 0.90, 0.55, 0.0};
  std::vector<double> neg(r.size()), zero(r.size(), 0.0);
  std::transform(r.begin(), r.end(), neg.begin(), [](double v) { return -v; });
  return Body(BodyTables{Profile(s, r), Profile(s, neg), Profile(s, zero), Profile(s, r), 2.0}, Vec3(5.3, y, -2.70),
              6.4);
}

LiftingSurface Wing() {
  LiftingSurfaceSpec w;
  w.root_leading_edge = Vec3(XOfStation(18.6), 0.0, -1.6);
  w.semispan = 24.05;  // 48.1 m span
  w.root_chord = 10.0;
  w.tip_chord = 2.2;
  w.le_sweep_deg = 33.0;
  w.dihedral_deg = 6.0;
  w.root_thickness = 0.15;
  w.tip_thickness = 0.10;
  w.camber = 0.02;
  w.mirrored = true;
  w.cap_m = 0.15;
  return LiftingSurface(w);
}

LiftingSurface Pylon(double y) {
  LiftingSurfaceSpec p;
  p.root_leading_edge = Vec3(3.3, y, -2.2);  // root buried in the nacelle, tip in the wing
  p.span_axis = Vec3(0, 0, 1);
  p.semispan = 1.35;
  p.root_chord = 6.0;
  p.tip_chord = 6.0;
  p.root_thickness = 0.08;
  p.tip_thickness = 0.08;
  p.cap_m = 0.10;
  return LiftingSurface(p);
}

LiftingSurface Stabilizer() {
  LiftingSurfaceSpec h;
  h.root_leading_edge = Vec3(XOfStation(41.0), 0.0, 0.9);
  h.semispan = 9.3;
  h.root_chord = 5.6;
  h.tip_chord = 1.8;
  h.le_sweep_deg = 37.0;
  h.dihedral_deg = 7.0;
  h.root_thickness = 0.11;
  h.tip_thickness = 0.09;
  h.mirrored = true;
  h.cap_m = 0.08;
  return LiftingSurface(h);
}

LiftingSurface Fin() {
  LiftingSurfaceSpec f;
  f.root_leading_edge = Vec3(XOfStation(38.0), 0.0, 1.5);
  f.span_axis = Vec3(0, 0, 1);
  f.semispan = 9.9;  // tip 11.4 m above the centre line
  f.root_chord = 9.5;
  f.tip_chord = 3.0;
  f.le_sweep_deg = 40.0;
  f.root_thickness = 0.11;
  f.tip_thickness = 0.10;
  f.cap_m = 0.12;
  return LiftingSurface(f);
}

/// Whether p is inside the view pyramid of a camera at `centre`.
bool InView(const Vec3& centre, const Vec3& p) {
  const Vec3 d = p - centre;
  const double z = d.dot(kCameraZ);
  return z > 0.0 && std::abs(d.dot(kCameraX)) < z * kTanHalfFovX && std::abs(d.dot(kCameraY)) < z * kTanHalfFovY;
}

RigClearance CheckRigClearance(const SceneModel& scene, const Body& fuselage_body) {
  RigClearance r;
  // Underside at the rig station: the lowest point of the section there.
  const double rig_station = kHalfLength - kCameraCentres[0].x();
  r.fuselage_bottom_at_rig_m = fuselage_body.tables().z_bottom(rig_station);
  r.lowest_near_rig_m = INFINITY;
  for (const Node& node : scene.nodes) {
    for (const Primitive& prim : node.primitives) {
      const Mesh& m = prim.mesh;
      for (const Vec3& p : m.positions) {
        if (std::abs(p.x() - kCameraCentres[0].x()) < 3.0 && std::abs(p.y()) < 1.5) {
          r.lowest_near_rig_m = std::min(r.lowest_near_rig_m, p.z());
        }
      }
      // Vertices, edge midpoints and centroids of every triangle.
      for (std::size_t k = 0; k < m.indices.size(); k += 3) {
        const Vec3& a = m.positions[m.indices[k]];
        const Vec3& b = m.positions[m.indices[k + 1]];
        const Vec3& c = m.positions[m.indices[k + 2]];
        for (const Vec3& q :
             {a, b, c, Vec3(0.5 * (a + b)), Vec3(0.5 * (b + c)), Vec3(0.5 * (c + a)), Vec3((a + b + c) / 3.0)}) {
          if (InView(kCameraCentres[0], q) || InView(kCameraCentres[1], q)) ++r.vertices_in_view;
        }
      }
    }
  }
  if (r.fuselage_bottom_at_rig_m <= kFuselageBottomLimit || r.lowest_near_rig_m < kLowestNearRigLimit ||
      r.vertices_in_view != 0) {
    throw Error("kc46: geometry violates the stereo rig clearance (bottom at rig " +
                std::to_string(r.fuselage_bottom_at_rig_m) + ", lowest near rig " +
                std::to_string(r.lowest_near_rig_m) + ", points in view " + std::to_string(r.vertices_in_view) + ")");
  }
  return r;
}

}  // namespace

SceneModel BuildKc46(RigClearance* clearance) {
  const Body fuselage_body = Fuselage();
  SceneModel scene;
  scene.name = "kc46";
  scene.materials.push_back(Material{"kc46_grey", {0.60, 0.62, 0.64, 1.0}, false, 0.0, 0.7});
  auto add = [&scene](const char* name, const Patch& patch) {
    scene.nodes.push_back(Node{name, {Primitive{Tessellate(patch, nullptr), 0}}});
  };
  add("fuselage", fuselage_body.MakePatch(140, 64));
  add("wing", Wing().MakePatch(100, 40, 6));
  add("stabilizer", Stabilizer().MakePatch(60, 28, 5));
  add("fin", Fin().MakePatch(36, 32, 5));
  add("engine_left", Engine(7.7).MakePatch(40, 32));
  add("engine_right", Engine(-7.7).MakePatch(40, 32));
  add("pylon_left", Pylon(7.7).MakePatch(10, 24, 4));
  add("pylon_right", Pylon(-7.7).MakePatch(10, 24, 4));
  add("camera_fairing", CameraFairing().MakePatch(40, 32));
  const RigClearance r = CheckRigClearance(scene, fuselage_body);
  if (clearance != nullptr) *clearance = r;
  return scene;
}

}  // namespace aar::scenes
