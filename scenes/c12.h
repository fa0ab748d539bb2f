// The receiver model: a Beechcraft C-12 Huron (King Air 200 class), with a
// procedurally painted texture atlas. See docs/scenes.md.
#pragma once

#include <cstdint>

#include "glb_writer.h"

namespace aar::scenes {

struct C12Options {
  int atlas_size = 2048;      ///< texture atlas width and height (texels)
  int colour_levels = 64;     ///< quantisation levels per colour channel (PNG size vs smoothness)
  std::uint64_t seed = 1200;  ///< seed of every noise field of the livery
};

/// Facts about the generated C-12, for the report.
struct C12Info {
  double reference_station_m = 0;  ///< reference point, metres aft of the nose tip
  double mac_m = 0;                ///< wing mean aerodynamic chord
  double mac_span_station_m = 0;   ///< |y| of the mean aerodynamic chord
  double texels_per_m = 0;         ///< nominal atlas density (every island at least this)
};

/// Builds the C-12: nodes fuselage, wing, nacelle_left, nacelle_right, fin,
/// stabilizer, all sharing one textured material. Origin = reference point
/// (fuselage centre line, quarter chord of the wing's mean aerodynamic chord,
/// cabin centre-line height).
SceneModel BuildC12(const C12Options& options, C12Info* info);

}  // namespace aar::scenes
