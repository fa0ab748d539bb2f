#include "aar/renderer/rolling_shutter.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "aar/error.h"

namespace aar {
namespace {

void CheckSize(int width, int height, const char* what, int frame_width, int frame_height) {
  if (width != frame_width || height != frame_height) {
    throw Error(std::string("rolling shutter: ") + what + " of " + std::to_string(width) + " x " +
                std::to_string(height) + " px, the bands are of " + std::to_string(frame_width) + " x " +
                std::to_string(frame_height));
  }
}

}  // namespace

std::vector<double> ReadoutBandOffsets(double readout_ms, int bands) {
  std::vector<double> offsets;
  for (int b = 0; b < bands; ++b) offsets.push_back(1e-3 * readout_ms * ((b + 0.5) / bands - 0.5));
  return offsets;
}

int ReadoutBand(double y, int height, int bands) {
  const double band = std::floor((y + 0.5) * bands / height);
  return static_cast<int>(std::clamp(band, 0.0, static_cast<double>(bands - 1)));
}

ReadoutBands::ReadoutBands(const Intrinsics& sensor, const Intrinsics& rendered, int bands)
    : width_(rendered.width_px), height_(rendered.height_px), bands_(bands) {
  if (bands < 1 || bands > kMaxReadoutBands) {
    throw Error("rolling shutter: " + std::to_string(bands) + " bands; expected 1 to " +
                std::to_string(kMaxReadoutBands));
  }
  band_.resize(static_cast<size_t>(width_) * height_);
  rows_.assign(bands, PixelRect{0, height_, width_, 0});
  for (int v = 0; v < height_; ++v) {
    for (int u = 0; u < width_; ++u) {
      // The pixel's ray, and the sensor row it lands on (through the lens;
      // beyond the lens model's fold, where no sensor pixel samples, its
      // undistorted row).
      const Eigen::Vector3d ray((u - rendered.cx_px) / rendered.fx_px, (v - rendered.cy_px) / rendered.fy_px, 1.0);
      const std::optional<Eigen::Vector2d> on_sensor = sensor.Project(ray);
      const double y = on_sensor ? on_sensor->y() : sensor.fy_px * ray.y() + sensor.cy_px;
      const int b = ReadoutBand(y, sensor.height_px, bands);
      band_[static_cast<size_t>(v) * width_ + u] = static_cast<uint16_t>(b);
      rows_[b].y0 = std::min(rows_[b].y0, v);
      rows_[b].y1 = std::max(rows_[b].y1, v + 1);
    }
  }
  for (PixelRect& r : rows_) {
    if (r.empty()) r = PixelRect{};
  }
}

void ReadoutBands::Composite(int band, const LinearImage& rendered, LinearImage& frame) const {
  CheckSize(rendered.width, rendered.height, "a band's render", width_, height_);
  CheckSize(frame.width, frame.height, "a frame", width_, height_);
  const PixelRect& rows = Rows(band);
  for (int v = rows.y0; v < rows.y1; ++v) {
    for (int u = 0; u < width_; ++u) {
      const size_t i = static_cast<size_t>(v) * width_ + u;
      if (band_[i] != band) continue;
      for (size_t c = 0; c < 3; ++c) frame.rgb[i * 3 + c] = rendered.rgb[i * 3 + c];
    }
  }
}

void ReadoutBands::Composite(int band, const GroundTruthImage& rendered, GroundTruthImage& frame) const {
  CheckSize(rendered.width, rendered.height, "a band's truth", width_, height_);
  CheckSize(frame.width, frame.height, "a frame's truth", width_, height_);
  const PixelRect& rows = Rows(band);
  for (int v = rows.y0; v < rows.y1; ++v) {
    for (int u = 0; u < width_; ++u) {
      const size_t i = static_cast<size_t>(v) * width_ + u;
      if (band_[i] != band) continue;
      frame.depth_m[i] = rendered.depth_m[i];
      frame.object_id[i] = rendered.object_id[i];
    }
  }
}

nlohmann::json RollingShutterJson(double readout_ms, int bands) {
  return {{"readout_ms", readout_ms},
          {"bands", bands},
          {"row_instants", "sample time + readout * ((r + 0.5) / height - 0.5) for sensor row r, top to bottom"},
          {"rendering",
           "the frame in `bands` equal bands of sensor rows, band b at sample time + readout * ((b + 0.5) / bands - "
           "0.5) (with a shutter: its exposure centred there); through a lens, a pinhole pixel takes the band of the "
           "sensor row it lands on"},
          {"truth", "depth and ids of each band at its instant; the sidecar's pose is the sample time's (mid-frame)"}};
}

}  // namespace aar
