#pragma once
// Bayer colour filter array (RGGB) and bilinear demosaicing
// (docs/rendering.md, "Sensor model").

#include <vector>

#include "aar/image.h"

namespace aar {

/// The channel (0 red, 1 green, 2 blue) the RGGB filter passes at a pixel:
/// even rows R G R G ..., odd rows G B G B ...
int RggbChannel(int row, int column);

/// Bilinear demosaicing of an RGGB mosaic (`mosaic[y * width + x]` is the
/// value of channel RggbChannel(y, x) there): a pixel keeps its own channel
/// and takes each other one as the mean of its nearest neighbours with that
/// channel (2 or 4 of them: the 4-neighbours for green, the edge or diagonal
/// neighbours for red and blue). Beyond the border the mosaic is mirrored
/// about the edge pixel (which keeps the RGGB phase). Needs width and height
/// of at least 2. A uniform grey mosaic gives back the same grey exactly.
LinearImage DemosaicRggbBilinear(const std::vector<float>& mosaic, int width, int height);

}  // namespace aar
