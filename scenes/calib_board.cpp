#include "calib_board.h"

namespace aar::scenes {

SceneModel BuildCalibBoard(const BoardSpec& spec) {
  // Cells of a (squares + 2 border) grid; cell (kx, ky) spans
  // [x0 + kx a, x0 + (kx + 1) a] x [y0 + ky a, y0 + (ky + 1) a]. Every cell is
  // its own quad but corner coordinates are exact multiples of a, so
  // neighbouring quads share edges bit for bit (no T-junctions, no cracks).
  const double a = spec.square_m;
  const int squares_x = spec.inner_corners_x + 1, squares_y = spec.inner_corners_y + 1;
  const int cells_x = squares_x + 2 * spec.border_squares, cells_y = squares_y + 2 * spec.border_squares;
  const int first =
      -1 - spec.border_squares;  // index of the first cell; square (0, 0) has its far corner at the origin
  auto grid = [&](int k) { return a * k; };
  const double zb = spec.backing_m;

  Mesh black, white, backing;
  const Vec3 front(0, 0, -1), back(0, 0, 1);
  for (int ky = 0; ky < cells_y; ++ky) {
    for (int kx = 0; kx < cells_x; ++kx) {
      const int ix = first + kx, iy = first + ky;  // cell lower corner in squares
      const double x0 = grid(ix), x1 = grid(ix + 1), y0 = grid(iy), y1 = grid(iy + 1);
      const bool border = kx < spec.border_squares || ky < spec.border_squares || kx >= cells_x - spec.border_squares ||
                          ky >= cells_y - spec.border_squares;
      // Square (sx, sy) counted from the top-left square (x < 0, y < 0), which is black.
      const int sx = kx - spec.border_squares, sy = ky - spec.border_squares;
      Mesh& face = (!border && (sx + sy) % 2 == 0) ? black : white;
      face.AddQuad(Vec3(x0, y0, 0), Vec3(x1, y0, 0), Vec3(x1, y1, 0), Vec3(x0, y1, 0), front);
      backing.AddQuad(Vec3(x0, y0, zb), Vec3(x1, y0, zb), Vec3(x1, y1, zb), Vec3(x0, y1, zb), back);
    }
  }
  // Slab edges, split at every grid line so they meet the face quads' corners.
  const double xa = grid(first), xb = grid(first + cells_x), ya = grid(first), yb = grid(first + cells_y);
  for (int kx = 0; kx < cells_x; ++kx) {
    const double x0 = grid(first + kx), x1 = grid(first + kx + 1);
    backing.AddQuad(Vec3(x0, ya, 0), Vec3(x1, ya, 0), Vec3(x1, ya, zb), Vec3(x0, ya, zb), Vec3(0, -1, 0));
    backing.AddQuad(Vec3(x0, yb, 0), Vec3(x1, yb, 0), Vec3(x1, yb, zb), Vec3(x0, yb, zb), Vec3(0, 1, 0));
  }
  for (int ky = 0; ky < cells_y; ++ky) {
    const double y0 = grid(first + ky), y1 = grid(first + ky + 1);
    backing.AddQuad(Vec3(xa, y0, 0), Vec3(xa, y1, 0), Vec3(xa, y1, zb), Vec3(xa, y0, zb), Vec3(-1, 0, 0));
    backing.AddQuad(Vec3(xb, y0, 0), Vec3(xb, y1, 0), Vec3(xb, y1, zb), Vec3(xb, y0, zb), Vec3(1, 0, 0));
  }

  SceneModel scene;
  scene.name = "calib_board";
  scene.materials = {Material{"board_black", {0.02, 0.02, 0.02, 1.0}, false},
                     Material{"board_white", {0.9, 0.9, 0.9, 1.0}, false},
                     Material{"board_backing", {0.15, 0.15, 0.15, 1.0}, false}};
  scene.nodes.push_back(Node{
      "board", {Primitive{std::move(black), 0}, Primitive{std::move(white), 1}, Primitive{std::move(backing), 2}}});
  return scene;
}

}  // namespace aar::scenes
