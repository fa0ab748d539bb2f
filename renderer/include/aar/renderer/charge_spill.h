#pragma once
// Blooming and smear (docs/rendering.md, "Sensor model"; sensor.h's
// blooming and smear): what a bright source does to the charge of the
// pixels in its column before the readout. Pure CPU; the sensor model
// applies it to the mean photo-electrons, before the shot noise.

#include <vector>

namespace aar {

struct ChargeSpillOptions {
  double full_well_e = 10000.0;  ///< a pixel's capacity [e-]
  double blooming = 0.0;         ///< share of each pixel's excess that spills along its column
  double smear = 0.0;            ///< transfer time over exposure time
};

/// In place, on `electrons` (row-major, `channels` interleaved values per
/// pixel; each channel's columns are separate, as a three-sensor camera's
/// are, and a mosaic is one channel): the smear, each value plus smear times
/// its column's mean; then the blooming: a pixel's excess over the full well,
/// times `blooming`, spills half up and half down its column, each
/// neighbour filled to the full well before the rest goes on, and what
/// passes the image's edge is lost; the rest of the excess is drained (the
/// pixel keeps its full well). No-op with both 0.
void SpillCharge(std::vector<double>& electrons, int width, int height, int channels,
                 const ChargeSpillOptions& options);

}  // namespace aar
