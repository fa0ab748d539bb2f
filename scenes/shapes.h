// Parametric airframe components: streamlined bodies (fuselages, nacelles,
// fairings) and lifting surfaces (wings, tailplanes, fins, pylons). Each
// builds a closed, outward-oriented Patch whose texture parameters are close
// to arc length, so a rectangle of the atlas maps onto it with roughly uniform
// texel density.
#pragma once

#include "geometry.h"

namespace aar::scenes {

/// Cross-section tables of a streamlined body, as functions of the station
/// s (metres aft of the body's nose tip, 0..length). Heights are body z,
/// half-widths body y, both relative to the body's axis point.
/// At s = 0 and s = length the half-width must be 0 and the top equal the
/// bottom, so the surface closes in a point at each end.
struct BodyTables {
  Profile z_top;          ///< top of the section
  Profile z_bottom;       ///< bottom of the section
  Profile z_breadth;      ///< height of the widest point (between bottom and top)
  Profile half_width;     ///< half of the widest breadth
  double exponent = 2.0;  ///< superellipse exponent of the section (2 = ellipse, larger = boxier)
};

/// A streamlined body of superelliptic sections along the -x body axis.
/// Texture parameters: u along the body (nose to tail, proportional to the
/// longest meridian's arc length), v around the section (v = 0 bottom, 0.25
/// the left (+y) side, 0.5 top, 0.75 right side).
class Body {
 public:
  /// `nose` is the nose tip's body position; the body extends aft to
  /// x = nose.x - length.
  Body(BodyTables tables, Vec3 nose, double length);

  Vec3 Point(double u, double v) const;
  double Station(double u) const;  ///< s of texture row u
  /// Normalised section height: -1 at the bottom, 0 at the widest point, +1 at the top.
  double SectionHeight(double v) const;
  const BodyTables& tables() const { return tables_; }
  /// Patch with `rings` + 1 sections (uniform in u) and `around` + 1 columns.
  Patch MakePatch(int rings, int around) const;

 private:
  BodyTables tables_;
  Vec3 nose_;
  double length_;
  Profile station_of_u_;  ///< arc-length reparametrisation u -> s
  double meridian_m_ = 0;
  double max_perimeter_m_ = 0;
};

/// Planform and section of a trapezoidal lifting surface with NACA 4-digit
/// style sections (closed trailing edge).
struct LiftingSurfaceSpec {
  Vec3 root_leading_edge;                              ///< leading edge of the root section (span station 0)
  Vec3 span_axis{0, 1, 0};                             ///< unit, root towards the (+) tip
  Vec3 chord_axis{1, 0, 0};                            ///< unit, trailing edge towards leading edge
  double semispan = 1.0;                               ///< root to tip along span_axis (m)
  double root_chord = 1.0, tip_chord = 1.0;            ///< m
  double le_sweep_deg = 0.0;                           ///< leading edge sweep (tips further aft for > 0)
  double dihedral_deg = 0.0;                           ///< tips raised along the thickness axis
  double root_thickness = 0.12, tip_thickness = 0.12;  ///< t/c
  double camber = 0.0;                                 ///< max camber / chord, at 40 % chord (NACA m)
  bool mirrored = false;  ///< spans -semispan..+semispan symmetric about the root (wings, tailplanes)
  double cap_m = 0.08;    ///< spanwise length over which each free end is rounded shut
};

/// Closed lifting surface. Thickness axis = chord_axis x span_axis ("upper"
/// side). Texture parameters: u along the span (from -semispan or the root to
/// the tip), v around the section: v = 0 trailing edge lower side, 0.5
/// leading edge, 1 trailing edge upper side (normalised arc length).
class LiftingSurface {
 public:
  explicit LiftingSurface(const LiftingSurfaceSpec& spec);

  Vec3 Point(double u, double v) const;
  /// Span station of texture row u (-semispan..semispan, or 0..semispan).
  double SpanStation(double u) const;
  /// Chord fraction (0 at the leading edge, 1 at the trailing edge) of column v.
  double ChordFraction(double v) const;
  static bool IsUpperSide(double v) { return v >= 0.5; }
  double Chord(double span_station) const;
  /// Leading-edge point at a span station (body axes).
  Vec3 LeadingEdge(double span_station) const;
  const LiftingSurfaceSpec& spec() const { return spec_; }
  /// Patch with `span_segments` rows between the rounded ends, `cap_segments`
  /// rows across each end and `chord_segments` columns around the section
  /// (cosine spaced: dense at the leading and trailing edges).
  Patch MakePatch(int span_segments, int chord_segments, int cap_segments) const;

 private:
  struct SpanPoint {
    double eta;    ///< span station
    double scale;  ///< thickness factor, < 1 in the rounded end caps, 0 at the very ends
  };
  SpanPoint SpanPointAt(double u) const;

  LiftingSurfaceSpec spec_;
  Vec3 thickness_axis_;
  double root_station_ = 0;  ///< -semispan (mirrored) or 0
  // The span parameter is linear in span station between the rounded end
  // caps and linear in the rounding angle within them.
  double u_root_cap_end_ = 0, u_tip_cap_start_ = 1;
  Profile sigma_of_v_;
  Profile v_of_sigma_;
  double span_param_m_ = 0;
  double max_perimeter_m_ = 0;
};

}  // namespace aar::scenes
