#pragma once
// A rolling shutter (docs/rendering.md, "Rolling shutter"; the rig's
// sensor.readout_ms): the sensor's rows are read out one after the other,
// top to bottom, so row r of H is exposed centred on
//   t(r) = sample time + readout * ((r + 0.5) / H - 0.5),
// the middle of the frame at the sample's time and the first and last rows
// `readout` apart. The frame is rendered in `bands` equal bands of rows, each
// with the scene at its centre's instant: a row's instant is off by at most
// readout / (2 bands). Through a lens, a rendered pinhole pixel belongs to
// the band of the sensor row it lands on. Pure CPU code, deterministic.

#include <cstdint>
#include <nlohmann/json_fwd.hpp>
#include <vector>

#include "aar/image.h"
#include "aar/renderer/geometry_rect.h"
#include "aar/rig.h"

namespace aar {

inline constexpr int kMaxReadoutBands = 1024;  ///< most bands a frame is rendered in

/// Offset of band b's instant from the sample's time [s], b = 0 .. bands - 1:
/// readout * ((b + 0.5) / bands - 0.5).
std::vector<double> ReadoutBandOffsets(double readout_ms, int bands);

/// The band of a sensor row at y (OpenCV pixel coordinates, row r's centre
/// at y = r) in an image of `height` rows: floor((y + 0.5) bands / height),
/// clamped to [0, bands).
int ReadoutBand(double y, int height, int bands);

/// Which band every pixel of one camera's render belongs to.
class ReadoutBands {
 public:
  /// `sensor` is the rig's camera; `rendered` the camera the scene is
  /// rendered with: the same for a pinhole rig, its pinhole stand-in (a grown
  /// image, lens_distortion.h) for a distorted one. Throws aar::Error for
  /// bands outside 1 .. kMaxReadoutBands.
  ReadoutBands(const Intrinsics& sensor, const Intrinsics& rendered, int bands);

  int bands() const { return bands_; }
  /// The rendered rows that hold band b's pixels (full width): a band's own
  /// rows for a pinhole rig, the rows between its highest and lowest pixel
  /// through a lens; empty for a band no rendered pixel falls in.
  const PixelRect& Rows(int band) const { return rows_.at(band); }
  /// Copies band b's pixels of `rendered` (the render at its instant) into
  /// `frame`; both of the rendered camera's size.
  void Composite(int band, const LinearImage& rendered, LinearImage& frame) const;
  void Composite(int band, const GroundTruthImage& rendered, GroundTruthImage& frame) const;

 private:
  int width_ = 0, height_ = 0, bands_ = 0;
  std::vector<uint16_t> band_;  // per rendered pixel, row-major
  std::vector<PixelRect> rows_;
};

/// frames.rolling_shutter of the manifest.
nlohmann::json RollingShutterJson(double readout_ms, int bands);

}  // namespace aar
