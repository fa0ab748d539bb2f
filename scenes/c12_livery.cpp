#include "c12_livery.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace aar::scenes {
namespace {

constexpr double kPi = std::numbers::pi;

// Paint colours (display RGB).
const Color kWhite{0.86, 0.86, 0.84};
const Color kBellyGrey{0.50, 0.52, 0.54};
const Color kUnderGrey{0.62, 0.63, 0.64};  // under wing and tailplane
const Color kCheatBlue{0.10, 0.17, 0.40};
const Color kPinstripeRed{0.66, 0.13, 0.10};
const Color kRadome{0.34, 0.35, 0.36};
const Color kAntiGlare{0.15, 0.16, 0.14};
const Color kGlass{0.06, 0.08, 0.11};
const Color kFrame{0.30, 0.31, 0.32};
const Color kBoot{0.07, 0.07, 0.07};  // pneumatic de-ice boots
const Color kWalkway{0.23, 0.23, 0.22};
const Color kInk{0.07, 0.07, 0.08};  // markings
const Color kSpinner{0.56, 0.57, 0.59};
const Color kIntake{0.05, 0.05, 0.05};
const Color kExhaust{0.12, 0.11, 0.10};
const Color kNavRed{0.75, 0.08, 0.06};
const Color kNavGreen{0.08, 0.60, 0.20};

// Multiplicative shades.
constexpr double kPanelLine = 0.55;
constexpr double kRivet = 0.80;
constexpr double kLineHalfWidth = 0.006;  // m
constexpr double kRivetRadius = 0.0045;   // m
constexpr double kRivetPitch = 0.045;     // m

// Weathering: wavelengths (m) and amplitudes of the luminance octaves.
constexpr std::array<double, 6> kOctaveWavelength = {0.035, 0.07, 0.14, 0.28, 0.56, 1.12};
constexpr std::array<double, 6> kOctaveAmplitude = {0.045, 0.05, 0.055, 0.06, 0.07, 0.08};

// Fuselage layout (stations in m aft of the nose tip).
constexpr std::array<double, 12> kFuselageJoints = {0.28, 1.25, 2.45,  3.95,  5.25,  6.55,
                                                    7.85, 9.15, 10.35, 11.45, 12.45, 13.16};
constexpr double kLapJointPitch = kPi / 6.0;  // longitudinal skin joints every 30 deg
constexpr double kFrameSpacing = 0.26;
constexpr double kCabinWindowFirst = 4.45, kCabinWindowPitch = 0.62;
constexpr int kCabinWindows = 7;

bool IsNear(double d, double half_width = kLineHalfWidth) { return std::abs(d) < half_width; }

/// Rivet dot on a row: `along` measured along the row, `across` from the row's centre line.
bool OnRivet(double along, double across, double pitch = kRivetPitch) {
  return std::abs(across) < kRivetRadius && DistanceToGrid(along, pitch) < kRivetRadius;
}

/// Outline of a rounded rectangle centred at (0, 0): true on a band of `width` inside its edge.
bool OnOutline(double x, double y, double hx, double hy, double r, double width = 2 * kLineHalfWidth) {
  return InRoundedRect(x, y, hx, hy, r) && !InRoundedRect(x, y, hx - width, hy - width, std::max(r - width, 0.0));
}

// A point of the fuselage surface in the coordinates its paint is laid out in.
struct FuselageSpot {
  Vec3 p;
  double s;       // station, m aft of the nose tip
  double zeta;    // -1 bottom, 0 widest, +1 top
  double phi;     // 0 bottom, pi/2 left side, pi top
  bool left;      // on the left side (+y)
  double radius;  // mean radius of the section
  double around;  // approximate arc length from the bottom centre line
};

FuselageSpot FuselageSpotAt(const Body& body, double u, double v) {
  FuselageSpot f;
  f.p = body.Point(u, v);
  f.s = body.Station(u);
  f.zeta = body.SectionHeight(v);
  f.phi = 2.0 * kPi * v;
  f.left = f.p.y() >= 0.0;
  const BodyTables& t = body.tables();
  f.radius = 0.5 * (t.half_width(f.s) + 0.5 * (t.z_top(f.s) - t.z_bottom(f.s)));
  f.around = f.phi * f.radius;
  return f;
}

// Colour, shade and weathering strength of a fuselage point before weathering.
struct FuselageFinish {
  Color color;
  double shade = 1.0;
  double glass_weather = 1.0;
};

// The paint scheme of the fuselage and its markings.
Color FuselagePaint(const FuselageSpot& f) {
  const double s = f.s, zeta = f.zeta;
  Color c = zeta < -0.52 ? kBellyGrey : kWhite;
  if (s > 0.5 && s < 12.9) {
    if (zeta > -0.42 && zeta < -0.20)
      c = kCheatBlue;
    else if (zeta > -0.16 && zeta < -0.12)
      c = kPinstripeRed;
  }
  if (s < kFuselageJoints.front()) c = kRadome;
  if (s > kFuselageJoints.back()) c = kRadome;  // tail cone cap with the tail light
  if (s > 1.45 && s < 2.47 && zeta > 0.5) c = kAntiGlare;

  // Markings: "U.S. ARMY" on both sides of the aft fuselage, reading correctly from outside.
  constexpr double kTextStation = 10.55, kTextZ = 0.26, kTextHeight = 0.24;
  if (TextInk("U.S. ARMY", f.left ? s - kTextStation : kTextStation - s, f.p.z() - kTextZ, kTextHeight)) c = kInk;
  return c;
}

// Darkens `shade` on the skin's joints, lap joints and the rivet rows of the laps and frames.
void ShadeSkinJoints(const FuselageSpot& f, double& shade) {
  for (double joint : kFuselageJoints) {
    if (IsNear(f.s - joint)) shade *= kPanelLine;
  }
  const double lap = DistanceToGrid(f.phi, kLapJointPitch, 0.5 * kLapJointPitch) * f.radius;
  if (IsNear(lap)) shade *= kPanelLine;
  if (OnRivet(f.s, lap - 0.02, 0.05)) shade *= kRivet;
  if (OnRivet(f.around, DistanceToGrid(f.s, kFrameSpacing, 0.3))) shade *= kRivet;
}

// Antennas on the belly and the spine, anti-collision beacons.
void PaintAntennasAndBeacons(const FuselageSpot& f, Color& c) {
  const double s = f.s, zeta = f.zeta;
  const Vec3& p = f.p;
  for (double station : {4.6, 6.9, 8.2}) {
    if (zeta < -0.97 && std::abs(p.y()) < 0.025 && std::abs(s - station) < 0.12) c = kInk;
  }
  for (double station : {4.0, 7.4}) {
    if (zeta > 0.97 && std::abs(p.y()) < 0.025 && std::abs(s - station) < 0.10) c = kInk;
  }
  if (std::hypot(s - 9.6, p.y()) < 0.05 && zeta > 0) c = kNavRed;
  if (std::hypot(s - 8.4, p.y()) < 0.05 && zeta < 0) c = kNavRed;
}

// Doors: airstair door (left, aft), emergency exit (right, over the wing).
void AddDoors(const FuselageSpot& f, FuselageFinish& finish) {
  const double s = f.s;
  const Vec3& p = f.p;
  if (f.left && OnOutline(s - 9.10, p.z() + 0.05, 0.35, 0.66, 0.08)) finish.shade *= kPanelLine;
  if (f.left && InRoundedRect(s - 9.36, p.z() - 0.02, 0.05, 0.018, 0.01)) finish.color = kInk;
  if (!f.left && OnOutline(s - (kCabinWindowFirst + 2 * kCabinWindowPitch), p.z() - 0.28, 0.28, 0.33, 0.06)) {
    finish.shade *= kPanelLine;
  }
}

// Glass where `inside`, its frame where `frame`: unshaded, the glass weathering less.
void Glaze(bool inside, bool frame, double zeta, FuselageFinish& finish) {
  if (frame) {
    finish.color = kFrame;
    finish.shade = 1.0;
  } else if (inside) {
    finish.color = kGlass + Color::Constant(0.05 * std::clamp(zeta, 0.0, 1.0));  // sky reflection towards the top
    finish.shade = 1.0;
    finish.glass_weather = 0.4;
  }
}

// Glazing: windscreen (two panes either side of a centre post), cockpit
// side windows, seven cabin windows a side.
void AddGlazing(const FuselageSpot& f, FuselageFinish& finish) {
  const double s = f.s, zeta = f.zeta;
  const Vec3& p = f.p;
  {
    const double aft_edge_zeta = 0.32 + 0.35 * (s - 2.48) / 0.58;
    const bool region = s > 2.48 && s < 3.06 && zeta > aft_edge_zeta;
    const bool pane = s > 2.51 && s < 3.03 && zeta > aft_edge_zeta + 0.05 && std::abs(p.y()) > 0.045;
    Glaze(pane, region && !pane, zeta, finish);
  }
  {
    const double x = s - 3.46, y = p.z() - 0.37;
    Glaze(InRoundedRect(x, y, 0.30, 0.17, 0.06), OnOutline(x, y, 0.32, 0.19, 0.07, 0.02), zeta, finish);
  }
  for (int k = 0; k < kCabinWindows; ++k) {
    const double x = s - (kCabinWindowFirst + k * kCabinWindowPitch), y = p.z() - 0.30;
    Glaze(InRoundedRect(x, y, 0.15, 0.18, 0.06), OnOutline(x, y, 0.165, 0.195, 0.07, 0.015), zeta, finish);
  }
}

}  // namespace

C12Livery::C12Livery(const C12Airframe& airframe, std::uint64_t seed)
    : airframe_(airframe),
      seed_(seed),
      octaves_{ValueNoise(seed + 1), ValueNoise(seed + 2), ValueNoise(seed + 3),
               ValueNoise(seed + 4), ValueNoise(seed + 5), ValueNoise(seed + 6)},
      streaks_(seed + 7),
      grime_(seed + 8),
      soot_(seed + 9) {
  // A different fixed orientation per octave keeps the lattices from lining up.
  for (int k = 0; k < kOctaves; ++k) {
    octave_rotations_[static_cast<std::size_t>(k)] =
        (Eigen::AngleAxisd(0.7 + 1.3 * k, Vec3::UnitZ()) * Eigen::AngleAxisd(0.4 + 0.9 * k, Vec3::UnitX()))
            .toRotationMatrix();
  }
}

Color C12Livery::Weather(const Color& paint, const Vec3& p, double strength) const {
  double luminance = 1.0;
  for (std::size_t k = 0; k < octaves_.size(); ++k) {
    luminance += strength * kOctaveAmplitude[k] * octaves_[k](octave_rotations_[k] * p / kOctaveWavelength[k]);
  }
  // Streaks along the airflow (long in x, narrow across).
  luminance += strength * 0.05 * streaks_(Vec3(p.x() / 1.5, p.y() / 0.05, p.z() / 0.05));
  // Grime patches: darker and browner where the coarse field is high.
  const double g = std::clamp(grime_(p / 0.9) * 1.6 - 0.3, 0.0, 1.0) * strength;
  const Color dirt{0.42, 0.39, 0.33};
  Color c = paint * luminance;
  c = c * (1.0 - 0.22 * g) + dirt * (0.22 * g) * luminance;
  // A floor of additive variation keeps dark paint (boots, glass) matchable.
  c += Color::Constant(0.025 * strength * octaves_[2](p / 0.12 + Vec3(17.0, 5.0, 3.0)));
  return c;
}

double C12Livery::PanelShade(std::int64_t part, std::int64_t i, std::int64_t j) const {
  return 1.0 + 0.07 * (Hash01(seed_, part, i, j) - 0.5);
}

double C12Livery::AccessPanel(std::int64_t part, std::int64_t i, std::int64_t j, double a0, double a1, double b0,
                              double b1, double a, double b) const {
  const std::uint64_t h = Hash64(seed_ + 100, part, i, j);
  if (h % 5 < 2) return 1.0;  // 60 % of the cells carry a panel
  auto u01 = [h](int k) { return static_cast<double>((h >> (8 * k + 8)) & 0xff) / 255.0; };
  const double hx = std::min(0.08 + 0.12 * u01(0), 0.5 * (a1 - a0) - 0.05);
  const double hy = std::min(0.06 + 0.10 * u01(1), 0.5 * (b1 - b0) - 0.05);
  if (hx <= 0.02 || hy <= 0.02) return 1.0;
  const double ca = a0 + 0.05 + hx + u01(2) * std::max(0.0, (a1 - a0) - 0.1 - 2 * hx);
  const double cb = b0 + 0.05 + hy + u01(3) * std::max(0.0, (b1 - b0) - 0.1 - 2 * hy);
  const double x = a - ca, y = b - cb;
  if (OnOutline(x, y, hx, hy, 0.02)) return kPanelLine;
  // Fasteners around the edge, 2.5 cm inside.
  const bool fastener_row = (std::abs(std::abs(x) - (hx - 0.025)) < kRivetRadius && std::abs(y) < hy - 0.02 &&
                             DistanceToGrid(y, 0.06) < kRivetRadius) ||
                            (std::abs(std::abs(y) - (hy - 0.025)) < kRivetRadius && std::abs(x) < hx - 0.02 &&
                             DistanceToGrid(x, 0.06) < kRivetRadius);
  if (fastener_row) return kRivet;
  if (InRoundedRect(x, y, hx, hy, 0.02)) return 1.0 + 0.06 * (u01(4) - 0.5);  // slightly different paint
  return 1.0;
}

Color C12Livery::Fuselage(double u, double v) const {
  const FuselageSpot f = FuselageSpotAt(airframe_.fuselage, u, v);
  FuselageFinish finish;
  finish.color = FuselagePaint(f);

  // Skin panels: shade per panel, joints, frames with rivet rows, access panels.
  const auto bay = static_cast<std::int64_t>(std::upper_bound(kFuselageJoints.begin(), kFuselageJoints.end(), f.s) -
                                             kFuselageJoints.begin());
  const auto strip = static_cast<std::int64_t>(std::floor((f.phi - 0.5 * kLapJointPitch) / kLapJointPitch));
  finish.shade = PanelShade(1, bay, strip);
  if (f.s > kFuselageJoints.front() && f.s < kFuselageJoints.back()) {
    ShadeSkinJoints(f, finish.shade);
    const bool panels_here = f.zeta < -0.1 || f.s < 2.4 || f.s > 9.6;
    if (panels_here && bay > 0 && bay < static_cast<std::int64_t>(kFuselageJoints.size())) {
      const double b0 = (0.5 * kLapJointPitch + static_cast<double>(strip) * kLapJointPitch) * f.radius;
      finish.shade *= AccessPanel(1, bay, strip, kFuselageJoints[static_cast<std::size_t>(bay - 1)],
                                  kFuselageJoints[static_cast<std::size_t>(bay)], b0, b0 + kLapJointPitch * f.radius,
                                  f.s, f.around);
    }
  }
  PaintAntennasAndBeacons(f, finish.color);
  AddDoors(f, finish);
  AddGlazing(f, finish);
  return Weather(finish.color * finish.shade, f.p, finish.glass_weather);
}

Color C12Livery::Wing(double u, double v) const {
  const LiftingSurface& w = airframe_.wing;
  const Vec3 p = w.Point(u, v);
  const double eta = w.SpanStation(u), a = std::abs(eta);
  const double xc = w.ChordFraction(v);
  const bool upper = LiftingSurface::IsUpperSide(v);
  const double chord = w.Chord(eta);
  const double xm = xc * chord;  // metres aft of the leading edge
  const double semispan = w.spec().semispan;
  const double nacelle = airframe_.nacelle_y;

  Color c = upper ? kWhite : kUnderGrey;
  // Ribs every 0.5 m from the wing root fairing, spars at 13 % and 70 % chord.
  constexpr double kRoot = 0.78, kRibPitch = 0.5;
  const auto rib_bay = static_cast<std::int64_t>(std::floor((a - kRoot) / kRibPitch));
  const std::int64_t zone = xc < 0.13 ? 0 : (xc < 0.70 ? 1 : 2);
  double shade = PanelShade(eta > 0 ? 2 : 3, rib_bay, zone + (upper ? 3 : 0));

  const bool boot_span = (a > kRoot && a < nacelle - 0.47) || (a > nacelle + 0.47 && a < semispan - 0.35);
  if (boot_span && xc < (upper ? 0.11 : 0.075)) c = kBoot;
  if (upper && a > 0.80 && a < 1.95 && xc > 0.16 && xc < 0.60) {
    c = kWalkway;
    if (OnOutline(a - 1.375, (xc - 0.38) * chord, 0.575, 0.22 * chord, 0.0, 0.02)) c = kInk;
  }
  if (a > semispan - 0.06 && xc < 0.3) c = eta > 0 ? kNavRed : kNavGreen;  // port red, starboard green

  if (a > kRoot && a < semispan - 0.1) {
    const double rib = DistanceToGrid(a, kRibPitch, kRoot);
    if (IsNear(rib)) shade *= kPanelLine;
    if (OnRivet(xm, rib - 0.02)) shade *= kRivet;
    for (double spar : {0.13, 0.70}) {
      const double d = (xc - spar) * chord;
      if (IsNear(d)) shade *= kPanelLine;
      if (OnRivet(a, d + 0.02)) shade *= kRivet;
    }
    if (xc > 0.16 && xc < 0.68 && OnRivet(a, DistanceToGrid(xm, 0.15), 0.06)) shade *= 0.9;  // stringers
    // Flaps (inboard and outboard of the nacelle) and ailerons behind a hinge line at 74 % chord.
    constexpr std::array<double, 6> kBreaks = {kRoot, 2.15, 3.05, 5.40, 5.45, 7.95};
    if (xc > 0.74) {
      for (double b : kBreaks) {
        if (IsNear(a - b)) shade *= kPanelLine;
      }
      if (eta > 0 && xc > 0.91 && OnOutline(a - 5.95, (xc - 0.96) * chord, 0.35, 0.05 * chord, 0.0)) {
        shade *= kPanelLine;  // aileron trim tab
      }
    }
    if (IsNear((xc - 0.74) * chord) && a < 7.95) shade *= kPanelLine;
    if (upper) {
      for (double centre : {1.45, 4.2}) {
        const double side_centre = eta > 0 ? centre : -centre;
        if (TextInk("NO STEP", side_centre - eta, (0.86 - xc) * chord, 0.08)) c = kInk;
      }
      if (std::hypot(a - 4.9, (xc - 0.30) * chord) < 0.06) {
        shade *= std::hypot(a - 4.9, (xc - 0.30) * chord) > 0.045 ? kPanelLine : 0.85;  // fuel filler
      }
    } else {
      // Inspection hatches in every other rib bay, fuel drains near the rear spar.
      if (rib_bay % 2 == 0) {
        const double r =
            std::hypot(a - (kRoot + (static_cast<double>(rib_bay) + 0.5) * kRibPitch), (xc - 0.42) * chord);
        if (std::abs(r - 0.085) < 0.006) shade *= kPanelLine;
      }
      if (std::hypot(DistanceToGrid(a, 1.0, 0.3), (xc - 0.66) * chord) < 0.012) c = kInk;
    }
  }
  // Exhaust soot over the wing beside the nacelles, streaked along the flow.
  if (upper) {
    const double d = std::abs(a - nacelle);
    if (d > 0.22 && d < 0.75 && xc > 0.2) {
      const double fade = std::clamp(1.0 - (xc - 0.2) / 0.9, 0.0, 1.0) * std::clamp((0.75 - d) / 0.25, 0.0, 1.0);
      const double streak = 0.5 + 0.5 * soot_(Vec3(p.x() / 0.8, p.y() / 0.04, 0.0));
      shade *= 1.0 - 0.45 * fade * streak;
    }
  }
  return Weather(c * shade, p);
}

Color C12Livery::Nacelle(const Body& body, double u, double v) const {
  const Vec3 p = body.Point(u, v);
  const double s = body.Station(u);
  const double zeta = body.SectionHeight(v);
  const double phi = 2.0 * kPi * v;
  const double side = std::abs(std::sin(phi));  // 1 on the inboard/outboard sides
  const bool left_nacelle = body.Point(0.0, 0.0).y() > 0;
  const BodyTables& t = body.tables();
  const double radius = 0.5 * (t.half_width(s) + 0.5 * (t.z_top(s) - t.z_bottom(s)));
  const double around = phi * radius;

  Color c = zeta > -0.35 ? kWhite : kBellyGrey;
  if (s < 0.42) c = s < 0.12 ? kFrame : kSpinner;
  constexpr std::array<double, 5> kCowlJoints = {0.42, 1.0, 1.75, 2.55, 3.55};
  const auto bay =
      static_cast<std::int64_t>(std::upper_bound(kCowlJoints.begin(), kCowlJoints.end(), s) - kCowlJoints.begin());
  double shade = PanelShade(left_nacelle ? 4 : 5, bay, zeta > 0 ? 1 : 0);
  if (s > kCowlJoints.front()) {
    for (double joint : kCowlJoints) {
      if (IsNear(s - joint)) shade *= kPanelLine;
    }
    if (OnRivet(around, DistanceToGrid(s, 0.2, 0.5))) shade *= kRivet;
    if (IsNear(p.y() - body.Point(0.0, 0.0).y()) && zeta < -0.5) shade *= kPanelLine;  // keel seam / gear doors
  }
  // Chin intake below the spinner.
  if (s > 0.50 && s < 0.85 && zeta < -0.62) c = (s < 0.54 || zeta > -0.66) ? kFrame : kIntake;
  // Cowl latches.
  for (double z_level : {-0.4, 0.45}) {
    if (std::abs(s - 1.75) < 0.04 && std::abs(zeta - z_level) < 0.03) c = kInk;
  }
  // Exhaust stacks on both sides and their soot trail.
  if (side > 0.6) {
    const double stack = std::hypot((s - 1.28) / 0.22, zeta / 0.28);
    if (stack < 1.0) c = stack < 0.7 ? kInk : kExhaust;
    if (s > 1.5 && s < 3.8 && std::abs(zeta) < 0.25 + 0.12 * (s - 1.5)) {
      const double fade = 1.0 - (s - 1.5) / 2.3;
      const double streak = 0.5 + 0.5 * soot_(Vec3(p.x() / 0.7, 0.0, p.z() / 0.035) + Vec3(0, 0, 9.0));
      shade *= 1.0 - 0.55 * fade * streak;
    }
  }
  // Main gear doors under the nacelle.
  if (zeta < -0.5 && OnOutline(s - 3.1, p.y() - body.Point(0.0, 0.0).y(), 0.8, 0.30, 0.05)) shade *= kPanelLine;
  return Weather(c * shade, p);
}

Color C12Livery::Fin(double u, double v) const {
  const LiftingSurface& f = airframe_.fin;
  const Vec3 p = f.Point(u, v);
  const double xc = f.ChordFraction(v);
  const double chord = f.Chord(f.SpanStation(u));
  const double s = airframe_.StationOfX(p.x());
  const bool left = p.y() >= 0.0;
  const double top = f.spec().root_leading_edge.z() + f.spec().semispan;

  Color c = kWhite;
  if (p.z() > top - 0.30) c = kCheatBlue;
  if (xc < 0.10 && p.z() > 0.75 && p.z() < top - 0.12) c = kBoot;
  auto reading = [&](double centre) { return left ? s - centre : centre - s; };
  if (TextInk("U.S. ARMY", reading(12.0), p.z() - 1.95, 0.13)) c = kInk;
  if (TextInk("84-24375", reading(11.95), p.z() - 1.50, 0.17)) c = kInk;

  constexpr double kRibPitch = 0.35;
  const double rib = DistanceToGrid(p.z(), kRibPitch, 0.8);
  double shade = PanelShade(6, static_cast<std::int64_t>(std::floor(p.z() / kRibPitch)), xc < 0.66 ? 0 : 1);
  if (p.z() > 0.7) {
    if (IsNear(rib)) shade *= kPanelLine;
    if (OnRivet(xc * chord, rib - 0.02)) shade *= kRivet;
    for (double spar : {0.12, 0.66}) {
      const double d = (xc - spar) * chord;
      if (IsNear(d)) shade *= kPanelLine;
      if (OnRivet(p.z(), d - 0.02)) shade *= kRivet;
    }
    if (xc > 0.9 && OnOutline(p.z() - 1.2, (xc - 0.95) * chord, 0.3, 0.05 * chord, 0.0)) shade *= kPanelLine;
  }
  return Weather(c * shade, p);
}

Color C12Livery::Stabilizer(double u, double v) const {
  const LiftingSurface& st = airframe_.stabilizer;
  const Vec3 p = st.Point(u, v);
  const double eta = st.SpanStation(u), a = std::abs(eta);
  const double xc = st.ChordFraction(v);
  const bool upper = LiftingSurface::IsUpperSide(v);
  const double chord = st.Chord(eta);
  const double semispan = st.spec().semispan;

  Color c = upper ? kWhite : kUnderGrey;
  if (xc < (upper ? 0.10 : 0.07) && a > 0.22 && a < semispan - 0.08) c = kBoot;
  constexpr double kRibPitch = 0.35;
  const double rib = DistanceToGrid(a, kRibPitch, 0.22);
  double shade = PanelShade(7, static_cast<std::int64_t>(std::floor(eta / kRibPitch)), upper ? 1 : 0);
  if (a > 0.22 && a < semispan - 0.08) {
    if (IsNear(rib)) shade *= kPanelLine;
    if (OnRivet(xc * chord, rib - 0.02)) shade *= kRivet;
    for (double spar : {0.12, 0.66}) {
      const double d = (xc - spar) * chord;
      if (IsNear(d)) shade *= kPanelLine;
      if (OnRivet(a, d + 0.02)) shade *= kRivet;
    }
    if (xc > 0.9 && OnOutline(a - 0.65, (xc - 0.95) * chord, 0.3, 0.05 * chord, 0.0)) shade *= kPanelLine;
  }
  return Weather(c * shade, p);
}

}  // namespace aar::scenes
