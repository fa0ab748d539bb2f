#include "c12.h"

#include <cmath>
#include <numbers>

#include "c12_airframe.h"
#include "c12_livery.h"
#include "png_writer.h"
#include "texture_synth.h"

namespace aar::scenes {
namespace {

// Published King Air 200 / C-12 figures the model is scaled to.
constexpr double kLength = 13.34;    // m, nose tip to tail cone tip
constexpr double kSemispan = 8.305;  // m, half of the 16.61 m span

// Wing planform (stations in m aft of the nose tip).
constexpr double kWingQuarterChordStation = 5.45;  // unswept quarter-chord line
constexpr double kWingRootChord = 2.30;            // at the centre line
constexpr double kWingTipChord = 1.05;
constexpr double kWingRootZ = -0.50;  // chord plane at the centre line (low wing)
constexpr double kWingDihedralDeg = 5.0;

constexpr double kNacelleY = 2.60;
constexpr double kNacelleNoseStation = 3.25;
constexpr double kNacelleLength = 4.60;

constexpr double kFinRootStation = 10.0;  // leading edge at the (buried) root section
constexpr double kFinRootZ = 0.30;
constexpr double kStabilizerZ = 2.80;  // T-tail: stabilizer chord plane at the fin tip

// Tessellation (about 54k triangles in all).
constexpr int kFuselageRings = 120, kFuselageAround = 80;
constexpr int kWingSpan = 120, kWingChord = 56, kWingCap = 6;
constexpr int kNacelleRings = 60, kNacelleAround = 40;
constexpr int kTailSpan = 36, kTailChord = 40, kTailCap = 5;

constexpr int kGutter = 6;  // texels of padding around every atlas island

double DegToRad(double d) { return d * std::numbers::pi / 180.0; }

/// Mean aerodynamic chord of the trapezoidal planform (centre line to tip):
/// its length, span station and the station of its quarter chord.
struct MeanAerodynamicChord {
  double length, span_station, quarter_chord_station;
};
MeanAerodynamicChord ComputeMeanAerodynamicChord(double root_le_station, double tan_le_sweep) {
  const double taper = kWingTipChord / kWingRootChord;
  const double mac = 2.0 / 3.0 * kWingRootChord * (1 + taper + taper * taper) / (1 + taper);
  const double y_mac = kSemispan / 3.0 * (1 + 2 * taper) / (1 + taper);
  return {mac, y_mac, root_le_station + y_mac * tan_le_sweep + 0.25 * mac};
}

BodyTables FuselageTables() {
  // Pointed nose rising to a sloped windscreen (2.45-3.1 m), constant cabin
  // section 1.46 m wide x 1.64 m high, tail cone sweeping up to the tip.
  const std::vector<double> s = {0.00, 0.12, 0.40, 0.85,  1.40,  2.00,  2.45,  2.80,   3.10,
                                 3.50, 8.90, 9.80, 10.80, 11.80, 12.60, 13.05, kLength};
  return BodyTables{Profile(s, {-0.30, -0.12, 0.04, 0.18, 0.29, 0.38, 0.44, 0.62, 0.76, 0.82, 0.82, 0.81, 0.77, 0.70,
                                0.60, 0.50, 0.36}),
                    Profile(s, {-0.30, -0.46, -0.60, -0.70, -0.77, -0.81, -0.82, -0.82, -0.82, -0.82, -0.82, -0.72,
                                -0.50, -0.22, 0.02, 0.18, 0.36}),
                    Profile(s, {-0.30, -0.30, -0.28, -0.24, -0.19, -0.13, -0.09, -0.06, -0.03, 0.00, 0.00, 0.01, 0.05,
                                0.12, 0.20, 0.26, 0.36}),
                    Profile(s, {0.00, 0.17, 0.33, 0.47, 0.58, 0.66, 0.70, 0.72, 0.73, 0.73, 0.73, 0.70, 0.60, 0.45,
                                0.28, 0.15, 0.00}),
                    2.2};
}

BodyTables NacelleTables() {
  // Spinner stub (propeller removed), cowling with a deep lower half holding
  // the gear well, tapering tail above the wing trailing edge. Heights are
  // relative to the propeller axis.
  const std::vector<double> s = {0.00, 0.10, 0.28, 0.45, 0.75, 1.20, 2.00, 2.80, 3.50, 4.10, 4.45, kNacelleLength};
  return BodyTables{Profile(s, {0.00, 0.10, 0.20, 0.27, 0.34, 0.38, 0.39, 0.36, 0.28, 0.17, 0.10, 0.06}),
                    Profile(s, {0.00, -0.10, -0.20, -0.32, -0.48, -0.56, -0.58, -0.52, -0.38, -0.20, -0.06, 0.06}),
                    Profile(s, {0.00, 0.00, 0.00, -0.02, -0.05, -0.07, -0.08, -0.07, -0.04, 0.00, 0.03, 0.06}),
                    Profile(s, {0.00, 0.10, 0.20, 0.27, 0.33, 0.36, 0.37, 0.35, 0.29, 0.18, 0.08, 0.00}), 2.0};
}

}  // namespace

C12Airframe MakeC12Airframe() {
  const double tan_le_sweep = (kWingRootChord - kWingTipChord) / (4.0 * kSemispan);  // straight quarter chord
  const double wing_root_le_station = kWingQuarterChordStation - 0.25 * kWingRootChord;
  const MeanAerodynamicChord mac = ComputeMeanAerodynamicChord(wing_root_le_station, tan_le_sweep);
  const double ref = mac.quarter_chord_station;
  auto x_of = [ref](double station) { return ref - station; };

  LiftingSurfaceSpec wing;
  wing.root_leading_edge = Vec3(x_of(wing_root_le_station), 0.0, kWingRootZ);
  wing.semispan = kSemispan;
  wing.root_chord = kWingRootChord;
  wing.tip_chord = kWingTipChord;
  wing.le_sweep_deg = std::atan(tan_le_sweep) * 180.0 / std::numbers::pi;
  wing.dihedral_deg = kWingDihedralDeg;
  wing.root_thickness = 0.18;  // NACA 23018 at the root, 23012 at the tip
  wing.tip_thickness = 0.12;
  wing.camber = 0.02;
  wing.mirrored = true;
  wing.cap_m = 0.08;

  LiftingSurfaceSpec fin;
  fin.root_leading_edge = Vec3(x_of(kFinRootStation), 0.0, kFinRootZ);
  fin.span_axis = Vec3(0, 0, 1);
  fin.semispan = kStabilizerZ - kFinRootZ;
  fin.root_chord = 2.90;
  fin.tip_chord = 1.45;
  fin.le_sweep_deg = 35.0;
  fin.root_thickness = 0.13;
  fin.tip_thickness = 0.11;
  fin.cap_m = 0.06;
  const LiftingSurface fin_surface(fin);

  LiftingSurfaceSpec stab;
  stab.root_leading_edge = fin_surface.LeadingEdge(fin.semispan);  // sits on the fin tip
  stab.semispan = 2.80;
  stab.root_chord = fin.tip_chord;
  stab.tip_chord = 0.80;
  stab.le_sweep_deg = 12.0;
  stab.root_thickness = 0.12;
  stab.tip_thickness = 0.10;
  stab.mirrored = true;
  stab.cap_m = 0.05;

  const double wing_z_at_nacelle = kWingRootZ + kNacelleY * std::tan(DegToRad(kWingDihedralDeg));
  const double nacelle_axis_z = wing_z_at_nacelle + 0.10;
  const double nacelle_nose_x = x_of(kNacelleNoseStation);

  return C12Airframe{
      ref,
      mac.length,
      mac.span_station,
      kNacelleY,
      Body(FuselageTables(), Vec3(x_of(0.0), 0.0, 0.0), kLength),
      LiftingSurface(wing),
      Body(NacelleTables(), Vec3(nacelle_nose_x, kNacelleY, nacelle_axis_z), kNacelleLength),
      Body(NacelleTables(), Vec3(nacelle_nose_x, -kNacelleY, nacelle_axis_z), kNacelleLength),
      fin_surface,
      LiftingSurface(stab),
  };
}

SceneModel BuildC12(const C12Options& options, C12Info* info) {
  const C12Airframe airframe = MakeC12Airframe();
  const C12Livery livery(airframe, options.seed);

  struct Part {
    const char* name;
    Patch patch;
    PaintFn paint;
  };
  const std::vector<Part> parts = {
      {"fuselage", airframe.fuselage.MakePatch(kFuselageRings, kFuselageAround),
       [&](double u, double v) { return livery.Fuselage(u, v); }},
      {"wing", airframe.wing.MakePatch(kWingSpan, kWingChord, kWingCap),
       [&](double u, double v) { return livery.Wing(u, v); }},
      {"nacelle_left", airframe.nacelle_left.MakePatch(kNacelleRings, kNacelleAround),
       [&](double u, double v) { return livery.Nacelle(airframe.nacelle_left, u, v); }},
      {"nacelle_right", airframe.nacelle_right.MakePatch(kNacelleRings, kNacelleAround),
       [&](double u, double v) { return livery.Nacelle(airframe.nacelle_right, u, v); }},
      {"fin", airframe.fin.MakePatch(kTailSpan, kTailChord, kTailCap),
       [&](double u, double v) { return livery.Fin(u, v); }},
      {"stabilizer", airframe.stabilizer.MakePatch(kTailSpan * 2, kTailChord, kTailCap),
       [&](double u, double v) { return livery.Stabilizer(u, v); }},
  };

  std::vector<const Patch*> patches;
  for (const Part& part : parts) patches.push_back(&part.patch);
  const AtlasLayout layout = PackAtlas(patches, options.atlas_size, options.atlas_size, kGutter);
  if (info != nullptr) {
    *info = C12Info{airframe.reference_station, airframe.mac, airframe.mac_span_station, layout.texels_per_m};
  }

  RgbImage atlas(options.atlas_size, options.atlas_size, options.colour_levels);
  SceneModel scene;
  scene.name = "c12";
  scene.materials.push_back(Material{"c12_livery", {1.0, 1.0, 1.0, 1.0}, true, 0.0, 0.35});
  for (std::size_t i = 0; i < parts.size(); ++i) {
    Bake(atlas, layout.rects[i], kGutter, parts[i].patch.periodic_v, parts[i].paint);
    scene.nodes.push_back(Node{parts[i].name, {Primitive{Tessellate(parts[i].patch, &layout.rects[i]), 0}}});
  }
  scene.texture_png = EncodePngRgb(atlas.width(), atlas.height(), atlas.pixels());
  return scene;
}

}  // namespace aar::scenes
