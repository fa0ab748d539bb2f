// The stereo calibration board of thesis section 3.3: a checkerboard with
// 16 x 17 inner corners, 0.5 m squares, a 0.5 m white border and a thin dark
// backing slab, built from exact geometry (no texture). See docs/scenes.md.
#pragma once

#include "glb_writer.h"

namespace aar::scenes {

struct BoardSpec {
  int inner_corners_x = 16;  ///< along board x (OpenCV pattern width)
  int inner_corners_y = 17;  ///< along board y (OpenCV pattern height)
  double square_m = 0.5;
  int border_squares = 1;   ///< white border width in squares (0.5 m)
  double backing_m = 0.02;  ///< backing slab thickness, behind the printed face (+z)
};

/// Board frame = OpenCV object frame: origin at the first inner corner, x
/// along the rows of `inner_corners_x` corners, y along the columns, z into
/// the board; inner corner (i, j) at (square i, square j, 0). The printed
/// face is the z = 0 plane facing -z; the square touching the origin at x < 0,
/// y < 0 is black. Materials: 0 black, 1 white, 2 backing.
SceneModel BuildCalibBoard(const BoardSpec& spec);

}  // namespace aar::scenes
