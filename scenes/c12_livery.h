// Procedural paint of the C-12 (internal to the generator): for every part a
// function from texture parameters (u, v) to colour. The paint scheme (white
// top, grey belly, blue cheat line, black de-ice boots, glazing, markings,
// panel lines, rivets) is defined on the surface in metres; weathering is
// solid 3-D noise of the body position (seamless across atlas islands) with
// wavelengths from 3.5 cm to 1.1 m, so stereo block matching finds texture at
// every range of interest.
#pragma once

#include <array>
#include <cstdint>

#include "c12_airframe.h"
#include "texture_synth.h"

namespace aar::scenes {

class C12Livery {
 public:
  C12Livery(const C12Airframe& airframe, std::uint64_t seed);

  Color Fuselage(double u, double v) const;
  Color Wing(double u, double v) const;
  Color Nacelle(const Body& nacelle, double u, double v) const;
  Color Fin(double u, double v) const;
  Color Stabilizer(double u, double v) const;

 private:
  /// Weathering of a painted colour at body position p: multi-octave
  /// luminance noise, flow-aligned streaks and patchy grime. `strength`
  /// scales it (glazing and rubber weather less).
  Color Weather(const Color& paint, const Vec3& p, double strength = 1.0) const;
  /// Per-panel shade variation (+-3.5 %) for panel (part, i, j).
  double PanelShade(std::int64_t part, std::int64_t i, std::int64_t j) const;
  /// Darkening factor of an outlined access panel possibly placed in the
  /// panel cell [a0, a1] x [b0, b1] (metres on the surface), at (a, b).
  double AccessPanel(std::int64_t part, std::int64_t i, std::int64_t j, double a0, double a1, double b0, double b1,
                     double a, double b) const;

  const C12Airframe& airframe_;
  std::uint64_t seed_;
  static constexpr int kOctaves = 6;
  std::array<ValueNoise, kOctaves> octaves_;
  std::array<Eigen::Matrix3d, kOctaves> octave_rotations_;
  ValueNoise streaks_, grime_, soot_;
};

}  // namespace aar::scenes
