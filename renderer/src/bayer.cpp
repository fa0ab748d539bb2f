#include "aar/renderer/bayer.h"

#include "aar/error.h"

namespace aar {
namespace {

// Mirrors an index about the edge pixels (-1 -> 1, n -> n - 2): same parity, so the same filter colour.
int Mirror(int i, int n) {
  if (i < 0) return -i;
  if (i >= n) return 2 * (n - 1) - i;
  return i;
}

}  // namespace

int RggbChannel(int row, int column) {
  const bool odd_row = (row & 1) != 0;
  const bool odd_column = (column & 1) != 0;
  if (odd_row != odd_column) return 1;
  return odd_row ? 2 : 0;
}

LinearImage DemosaicRggbBilinear(const std::vector<float>& mosaic, int width, int height) {
  if (width < 2 || height < 2 || mosaic.size() != static_cast<size_t>(width) * height) {
    throw Error("Bayer demosaicing needs a mosaic of at least 2 x 2 pixels, width x height values");
  }
  const auto at = [&](int y, int x) {
    return mosaic[static_cast<size_t>(Mirror(y, height)) * width + Mirror(x, width)];
  };
  LinearImage out;
  out.width = width;
  out.height = height;
  out.rgb.resize(static_cast<size_t>(width) * height * 3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      // Sums in pairs, so equal values give their value back exactly.
      const int own = RggbChannel(y, x);
      const float centre = at(y, x);
      const float cross = ((at(y - 1, x) + at(y + 1, x)) + (at(y, x - 1) + at(y, x + 1))) * 0.25f;
      const float diagonal = ((at(y - 1, x - 1) + at(y - 1, x + 1)) + (at(y + 1, x - 1) + at(y + 1, x + 1))) * 0.25f;
      const float along_row = (at(y, x - 1) + at(y, x + 1)) * 0.5f;
      const float along_column = (at(y - 1, x) + at(y + 1, x)) * 0.5f;
      float rgb[3];
      rgb[own] = centre;
      if (own == 1) {
        // Green: red and blue sit along the row on one side of the pattern, along the column on the other.
        const bool red_along_row = (y & 1) == 0;
        rgb[0] = red_along_row ? along_row : along_column;
        rgb[2] = red_along_row ? along_column : along_row;
      } else {
        rgb[1] = cross;
        rgb[2 - own] = diagonal;
      }
      float* pixel = &out.rgb[3 * (static_cast<size_t>(y) * width + x)];
      pixel[0] = rgb[0];
      pixel[1] = rgb[1];
      pixel[2] = rgb[2];
    }
  }
  return out;
}

}  // namespace aar
