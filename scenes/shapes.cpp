#include "shapes.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <utility>

#include "aar/error.h"

namespace aar::scenes {
namespace {

constexpr double kPi = std::numbers::pi;

/// sign(x) * |x|^e
double SignedPow(double x, double e) { return std::copysign(std::pow(std::abs(x), e), x); }

/// NACA 4-digit half thickness (closed trailing edge) at chord fraction x, per unit chord.
double NacaHalfThickness(double x, double t) {
  if (x >= 1.0) return 0.0;  // exactly closed trailing edge (the polynomial leaves ~1e-17)
  return 5.0 * t * (0.2969 * std::sqrt(x) - 0.1260 * x - 0.3516 * x * x + 0.2843 * x * x * x - 0.1036 * x * x * x * x);
}

/// NACA 4-digit camber line (maximum `m` at 40 % chord), per unit chord.
double NacaCamber(double x, double m) {
  constexpr double p = 0.4;
  if (x < p) return m / (p * p) * (2 * p * x - x * x);
  return m / ((1 - p) * (1 - p)) * ((1 - 2 * p) + 2 * p * x - x * x);
}

/// Section parameter sigma in [0, 1] -> chord fraction (cosine spacing):
/// 0 trailing edge (lower), 0.5 leading edge, 1 trailing edge (upper).
double ChordFractionOfSigma(double sigma) { return 0.5 * (1.0 + std::cos(2.0 * kPi * sigma)); }

/// Section point (chordwise from the leading edge, along the thickness axis), per unit chord.
Vec2 SectionPoint(double sigma, double thickness, double camber) {
  const double x = ChordFractionOfSigma(sigma);
  const double half = NacaHalfThickness(x, thickness);
  return {x, NacaCamber(x, camber) + (sigma >= 0.5 ? half : -half)};
}

}  // namespace

// ---------------------------------------------------------------------------
// Body

namespace {

Vec3 BodySectionPoint(const BodyTables& t, const Vec3& nose, double s, double phi) {
  const double e = 2.0 / t.exponent;
  const double zw = t.z_breadth(s);
  const double zeta = SignedPow(-std::cos(phi), e);
  const double z = zeta >= 0 ? zw + zeta * (t.z_top(s) - zw) : zw + zeta * (zw - t.z_bottom(s));
  const double y = t.half_width(s) * SignedPow(std::sin(phi), e);
  return nose + Vec3(-s, y, z);
}

}  // namespace

Body::Body(BodyTables tables, Vec3 nose, double length)
    : tables_(std::move(tables)), nose_(std::move(nose)), length_(length) {
  // Reparametrise u by the arc length of the longest meridian (the largest
  // step over a set of meridians, per station step), so texels are never
  // stretched along the body, even on the steep nose and tail.
  constexpr int kSteps = 4000;
  constexpr int kMeridians = 32;
  constexpr int kAround = 256;
  std::vector<double> arc{0.0}, stations{0.0};
  double total = 0.0;
  for (int i = 1; i <= kSteps; ++i) {
    const double s0 = length_ * (i - 1) / kSteps, s1 = length_ * i / kSteps;
    double step = 0.0;
    for (int k = 0; k < kMeridians; ++k) {
      const double phi = 2.0 * kPi * k / kMeridians;
      step = std::max(step,
                      (BodySectionPoint(tables_, nose_, s1, phi) - BodySectionPoint(tables_, nose_, s0, phi)).norm());
    }
    total += step;
    arc.push_back(total);
    stations.push_back(s1);
    if (i % 20 == 0) {
      double perimeter = 0.0;
      for (int k = 0; k < kAround; ++k) {
        perimeter += (BodySectionPoint(tables_, nose_, s1, 2.0 * kPi * (k + 1) / kAround) -
                      BodySectionPoint(tables_, nose_, s1, 2.0 * kPi * k / kAround))
                         .norm();
      }
      max_perimeter_m_ = std::max(max_perimeter_m_, perimeter);
    }
  }
  meridian_m_ = total;
  for (double& a : arc) a /= total;
  station_of_u_ = Profile(std::move(arc), std::move(stations));
}

double Body::Station(double u) const { return station_of_u_(u); }

double Body::SectionHeight(double v) const { return SignedPow(-std::cos(2.0 * kPi * v), 2.0 / tables_.exponent); }

Vec3 Body::Point(double u, double v) const {
  return BodySectionPoint(tables_, nose_, Station(u), 2.0 * kPi * (v - std::floor(v)));  // v = 1 is exactly v = 0
}

Patch Body::MakePatch(int rings, int around) const {
  Patch p;
  p.point = [self = std::make_shared<Body>(*this)](double u, double v) { return self->Point(u, v); };
  p.u_samples = UniformSamples(rings);
  p.v_samples = UniformSamples(around);
  p.periodic_v = true;
  p.length_u_m = meridian_m_;
  p.length_v_m = max_perimeter_m_;
  return p;
}

// ---------------------------------------------------------------------------
// LiftingSurface

LiftingSurface::LiftingSurface(const LiftingSurfaceSpec& spec) : spec_(spec) {
  if (spec_.cap_m <= 0 || spec_.cap_m * 2 >= spec_.semispan) {
    throw Error("LiftingSurface: cap length must be in (0, semispan / 2)");
  }
  thickness_axis_ = spec_.chord_axis.cross(spec_.span_axis).normalized();

  // Span parameter: each rounded end is parametrised by its rounding angle
  // and gets the arc length of its quarter ellipse (bounded by pi/2 times the
  // larger of cap length and half thickness); the rest is linear in span.
  root_station_ = spec_.mirrored ? -spec_.semispan : 0.0;
  const double root_half =
      0.5 * (spec_.mirrored ? spec_.tip_thickness * spec_.tip_chord : spec_.root_thickness * spec_.root_chord);
  const double tip_half = 0.5 * spec_.tip_thickness * spec_.tip_chord;
  const double root_cap = 0.5 * kPi * std::max(spec_.cap_m, root_half);
  const double tip_cap = 0.5 * kPi * std::max(spec_.cap_m, tip_half);
  const double middle = spec_.semispan - root_station_ - 2 * spec_.cap_m;
  span_param_m_ = root_cap + middle + tip_cap;
  u_root_cap_end_ = root_cap / span_param_m_;
  u_tip_cap_start_ = (root_cap + middle) / span_param_m_;

  // Section parameter: v = normalised arc length of a mid-span section.
  constexpr int kSteps = 4000;
  const double t_ref = 0.5 * (spec_.root_thickness + spec_.tip_thickness);
  std::vector<double> sigma{0.0}, arc{0.0};
  double total = 0.0;
  for (int i = 1; i <= kSteps; ++i) {
    const double s0 = static_cast<double>(i - 1) / kSteps, s1 = static_cast<double>(i) / kSteps;
    total += (SectionPoint(s1, t_ref, spec_.camber) - SectionPoint(s0, t_ref, spec_.camber)).norm();
    sigma.push_back(s1);
    arc.push_back(total);
  }
  for (double& a : arc) a /= total;
  const double max_chord = std::max(spec_.root_chord, spec_.tip_chord);
  const double max_t = std::max(spec_.root_thickness, spec_.tip_thickness);
  // Perimeter of the largest section, allowing for its thickness above t_ref.
  max_perimeter_m_ = total * max_chord * (1.0 + 0.5 * (max_t - t_ref));
  sigma_of_v_ = Profile(arc, sigma);
  v_of_sigma_ = Profile(std::move(sigma), std::move(arc));
}

LiftingSurface::SpanPoint LiftingSurface::SpanPointAt(double u) const {
  const double e1 = root_station_ + spec_.cap_m, e2 = spec_.semispan - spec_.cap_m;
  u = std::clamp(u, 0.0, 1.0);
  // Within a cap: rounding angle a (0 where the cap starts, pi/2 at the end),
  // station advanced by cap sin(a), thickness scaled by cos(a), exactly 0 at
  // the end so the surface closes.
  auto in_cap = [&](double start, double direction, double fraction) {
    const double angle = 0.5 * kPi * fraction;
    return SpanPoint{start + direction * spec_.cap_m * std::sin(angle), fraction >= 1.0 ? 0.0 : std::cos(angle)};
  };
  if (u < u_root_cap_end_) return in_cap(e1, -1.0, 1.0 - u / u_root_cap_end_);
  if (u > u_tip_cap_start_) return in_cap(e2, 1.0, (u - u_tip_cap_start_) / (1.0 - u_tip_cap_start_));
  return {e1 + (e2 - e1) * (u - u_root_cap_end_) / (u_tip_cap_start_ - u_root_cap_end_), 1.0};
}

double LiftingSurface::SpanStation(double u) const { return SpanPointAt(u).eta; }

double LiftingSurface::ChordFraction(double v) const { return ChordFractionOfSigma(sigma_of_v_(v)); }

double LiftingSurface::Chord(double eta) const {
  return spec_.root_chord + (spec_.tip_chord - spec_.root_chord) * std::abs(eta) / spec_.semispan;
}

Vec3 LiftingSurface::LeadingEdge(double eta) const {
  const double a = std::abs(eta);
  return spec_.root_leading_edge + spec_.span_axis * eta +
         thickness_axis_ * (a * std::tan(spec_.dihedral_deg * kPi / 180.0)) -
         spec_.chord_axis * (a * std::tan(spec_.le_sweep_deg * kPi / 180.0));
}

Vec3 LiftingSurface::Point(double u, double v) const {
  const auto [eta, scale] = SpanPointAt(u);
  const double a = std::abs(eta) / spec_.semispan;
  const double t = (spec_.root_thickness + (spec_.tip_thickness - spec_.root_thickness) * a) * scale;
  const Vec2 q = SectionPoint(sigma_of_v_(v), t, spec_.camber) * Chord(eta);
  return LeadingEdge(eta) - spec_.chord_axis * q.x() + thickness_axis_ * q.y();
}

Patch LiftingSurface::MakePatch(int span_segments, int chord_segments, int cap_segments) const {
  Patch p;
  p.point = [self = std::make_shared<LiftingSurface>(*this)](double u, double v) { return self->Point(u, v); };
  // Rows: uniform in the rounding angle over each end cap, uniform in span between.
  std::vector<double> rows;
  for (int k = 0; k < cap_segments; ++k) rows.push_back(u_root_cap_end_ * k / cap_segments);
  for (int k = 0; k < span_segments; ++k) {
    rows.push_back(u_root_cap_end_ + (u_tip_cap_start_ - u_root_cap_end_) * k / span_segments);
  }
  for (int k = 0; k < cap_segments; ++k) {
    rows.push_back(u_tip_cap_start_ + (1.0 - u_tip_cap_start_) * k / cap_segments);
  }
  rows.push_back(1.0);
  p.u_samples = std::move(rows);
  for (int j = 0; j <= chord_segments; ++j) {
    p.v_samples.push_back(v_of_sigma_(static_cast<double>(j) / chord_segments));
  }
  p.periodic_v = false;
  p.length_u_m = span_param_m_;
  p.length_v_m = max_perimeter_m_;
  return p;
}

}  // namespace aar::scenes
