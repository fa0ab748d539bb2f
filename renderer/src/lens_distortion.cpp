#include "aar/renderer/lens_distortion.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "aar/error.h"
#include "aar/renderer/geometry_rect.h"

namespace aar {
namespace {

// Lanczos-3 kernel sinc(t) sinc(t / 3), tabulated on [0, 3] (linear
// interpolation between entries, error below 1e-7).
constexpr int kTablePerUnit = 4096;

const std::vector<double>& LanczosTable() {
  static const std::vector<double> table = [] {
    std::vector<double> t(kLanczosLobes * kTablePerUnit + 2, 0.0);
    t[0] = 1.0;
    for (size_t i = 1; i + 1 < t.size(); ++i) {
      const double x = static_cast<double>(i) / kTablePerUnit;
      if (x >= kLanczosLobes) break;
      const double px = M_PI * x;
      t[i] = kLanczosLobes * std::sin(px) * std::sin(px / kLanczosLobes) / (px * px);
    }
    return t;
  }();
  return table;
}

double Lanczos(double x) {
  const double a = std::abs(x) * kTablePerUnit;
  if (a >= kLanczosLobes * kTablePerUnit) return 0.0;
  const auto& table = LanczosTable();
  const size_t i = static_cast<size_t>(a);
  const double f = a - static_cast<double>(i);
  return table[i] + f * (table[i + 1] - table[i]);
}

// One output pixel's source: position in the unextended pinhole image and the
// footprint scale per axis.
struct Source {
  double x = 0.0, y = 0.0;
  double scale_x = 1.0, scale_y = 1.0;
};

Source SourceOf(const Intrinsics& k, int u, int v, const std::string& where) {
  const Eigen::Vector2d distorted((u - k.cx_px) / k.fx_px, (v - k.cy_px) / k.fy_px);
  const std::optional<Eigen::Vector2d> x = Undistort(k.distortion, distorted);
  if (!x) {
    throw Error(where + ": lens distortion (" + DescribeDistortion(k.distortion) +
                ") has no undistorted ray for pixel (" + std::to_string(u) + ", " + std::to_string(v) + ")");
  }
  // d(source pixel) / d(output pixel) = diag(fx, fy) J^-1 diag(1/fx, 1/fy).
  const Eigen::Matrix2d inverse = DistortJacobian(k.distortion, *x).inverse();
  const double a = inverse(0, 0), b = inverse(0, 1) * k.fx_px / k.fy_px;
  const double c = inverse(1, 0) * k.fy_px / k.fx_px, d = inverse(1, 1);
  Source s;
  s.x = k.fx_px * x->x() + k.cx_px;
  s.y = k.fy_px * x->y() + k.cy_px;
  // The output pixel's footprint in the source: its bounding box per axis,
  // never below one source pixel (then the filter interpolates).
  s.scale_x = std::max(1.0, std::abs(a) + std::abs(b));
  s.scale_y = std::max(1.0, std::abs(c) + std::abs(d));
  return s;
}

}  // namespace

PixelMargin LensResampler::RequiredMargin(const Intrinsics& k, const std::string& where) {
  double x0 = 0.0, y0 = 0.0, x1 = k.width_px - 1.0, y1 = k.height_px - 1.0;
  for (int v = 0; v < k.height_px; ++v) {
    for (int u = 0; u < k.width_px; ++u) {
      // Only the border can reach outside for a one-to-one map, but the
      // interior costs little and makes no assumption.
      const Source s = SourceOf(k, u, v, where);
      x0 = std::min(x0, s.x - kLanczosLobes * s.scale_x);
      x1 = std::max(x1, s.x + kLanczosLobes * s.scale_x);
      y0 = std::min(y0, s.y - kLanczosLobes * s.scale_y);
      y1 = std::max(y1, s.y + kLanczosLobes * s.scale_y);
    }
  }
  PixelMargin m;
  m.left = static_cast<int>(std::ceil(-x0)) + 1;
  m.top = static_cast<int>(std::ceil(-y0)) + 1;
  m.right = static_cast<int>(std::ceil(x1 - (k.width_px - 1.0))) + 1;
  m.bottom = static_cast<int>(std::ceil(y1 - (k.height_px - 1.0))) + 1;
  return m;
}

LensResampler::LensResampler(const Intrinsics& k, const PixelMargin& margin, const std::string& where)
    : width_(k.width_px), height_(k.height_px) {
  pinhole_ = k;
  pinhole_.distortion = BrownConrady{};
  pinhole_.width_px = k.width_px + margin.left + margin.right;
  pinhole_.height_px = k.height_px + margin.top + margin.bottom;
  pinhole_.cx_px = k.cx_px + margin.left;
  pinhole_.cy_px = k.cy_px + margin.top;
  if (pinhole_.width_px > kMaxPinholeSidePx || pinhole_.height_px > kMaxPinholeSidePx) {
    throw Error(where + ": lens distortion (" + DescribeDistortion(k.distortion) + ") needs a pinhole render of " +
                std::to_string(pinhole_.width_px) + " x " + std::to_string(pinhole_.height_px) + " px (at most " +
                std::to_string(kMaxPinholeSidePx) + " per side)");
  }
  const size_t pixels = static_cast<size_t>(width_) * height_;
  source_x_.resize(pixels);
  source_y_.resize(pixels);
  scale_x_.resize(pixels);
  scale_y_.resize(pixels);
  for (int v = 0; v < height_; ++v) {
    for (int u = 0; u < width_; ++u) {
      const Source s = SourceOf(k, u, v, where);
      const size_t i = static_cast<size_t>(v) * width_ + u;
      source_x_[i] = s.x + margin.left;
      source_y_[i] = s.y + margin.top;
      scale_x_[i] = s.scale_x;
      scale_y_[i] = s.scale_y;
      const double reach_x = kLanczosLobes * s.scale_x, reach_y = kLanczosLobes * s.scale_y;
      max_reach_y_ = std::max(max_reach_y_, reach_y);
      if (source_x_[i] - reach_x < 0.0 || source_y_[i] - reach_y < 0.0 ||
          source_x_[i] + reach_x > pinhole_.width_px - 1.0 || source_y_[i] + reach_y > pinhole_.height_px - 1.0) {
        throw Error(where + ": the pinhole margin does not cover pixel (" + std::to_string(u) + ", " +
                    std::to_string(v) + ")");
      }
    }
  }
}

namespace {

// The smallest rectangle of pixels where `a` and `b` (same size) differ, bit
// for bit; empty when they are equal.
PixelRect ChangedPixels(const LinearImage& a, const LinearImage& b) {
  PixelRect changed{a.width, a.height, 0, 0};
  const size_t row_floats = static_cast<size_t>(a.width) * 3;
  for (int y = 0; y < a.height; ++y) {
    const float* ra = &a.rgb[y * row_floats];
    const float* rb = &b.rgb[y * row_floats];
    if (std::memcmp(ra, rb, row_floats * sizeof(float)) == 0) continue;
    int x0 = 0, x1 = a.width - 1;
    while (std::memcmp(ra + 3 * x0, rb + 3 * x0, 3 * sizeof(float)) == 0) ++x0;
    while (std::memcmp(ra + 3 * x1, rb + 3 * x1, 3 * sizeof(float)) == 0) --x1;
    changed.x0 = std::min(changed.x0, x0);
    changed.x1 = std::max(changed.x1, x1 + 1);
    changed.y0 = std::min(changed.y0, y);
    changed.y1 = y + 1;
  }
  return changed;
}

}  // namespace

LinearImage LensResampler::ResampleColor(const LinearImage& in) const {
  if (in.width != pinhole_.width_px || in.height != pinhole_.height_px) {
    throw Error("lens resampling: pinhole image has the wrong size");
  }
  const std::lock_guard<std::mutex> lock(cache_->mutex);
  const bool cached = cache_->in.width == in.width && cache_->in.height == in.height;
  const PixelRect changed = cached ? ChangedPixels(cache_->in, in) : PixelRect{0, 0, in.width, in.height};
  LinearImage out;
  if (cached) {
    out = cache_->out;
  } else {
    out.width = width_;
    out.height = height_;
    out.rgb.resize(static_cast<size_t>(width_) * height_ * 3);
  }
  if (changed.x0 < changed.x1 && changed.y0 < changed.y1) {
    // run[p]: how many pixels from p rightwards, p included, have p's colour
    // (bit for bit), so that a footprint of one colour is recognised with one
    // look per row.
    // (Only on the rows the recomputed pixels' footprints can reach.)
    std::vector<uint32_t> run(static_cast<size_t>(in.width) * in.height);
    const int reach_rows = static_cast<int>(std::ceil(max_reach_y_)) + 1;
    for (int y = std::max(0, changed.y0 - reach_rows); y < std::min(in.height, changed.y1 + reach_rows); ++y) {
      const size_t row = static_cast<size_t>(y) * in.width;
      run[row + in.width - 1] = 1;
      for (int x = in.width - 2; x >= 0; --x) {
        run[row + x] = std::memcmp(&in.rgb[(row + x) * 3], &in.rgb[(row + x + 1) * 3], 3 * sizeof(float)) == 0
                           ? run[row + x + 1] + 1
                           : 1;
      }
    }
    for (size_t i = 0; i < source_x_.size(); ++i) {
      // Only the pixels whose footprint reaches a changed pinhole pixel.
      const double reach_x = kLanczosLobes * scale_x_[i], reach_y = kLanczosLobes * scale_y_[i];
      if (source_x_[i] + reach_x < changed.x0 - 1 || source_x_[i] - reach_x > changed.x1 ||
          source_y_[i] + reach_y < changed.y0 - 1 || source_y_[i] - reach_y > changed.y1) {
        continue;
      }
      ResamplePixel(i, in, run, out);
    }
  }
  cache_->in = in;
  cache_->out = out;
  return out;
}

void LensResampler::ResamplePixel(size_t i, const LinearImage& in, const std::vector<uint32_t>& run,
                                  LinearImage& out) const {
  const auto same = [&in](size_t p, size_t q) {
    return std::memcmp(&in.rgb[p * 3], &in.rgb[q * 3], 3 * sizeof(float)) == 0;
  };
  const double sx = source_x_[i], sy = source_y_[i];
  const double scx = scale_x_[i], scy = scale_y_[i];
  const int x0 = static_cast<int>(std::ceil(sx - kLanczosLobes * scx));
  const int x1 = static_cast<int>(std::floor(sx + kLanczosLobes * scx));
  const int y0 = static_cast<int>(std::ceil(sy - kLanczosLobes * scy));
  const int y1 = static_cast<int>(std::floor(sy + kLanczosLobes * scy));
  // Relative to the nearest sample, so that a uniform neighbourhood (the
  // sky) is reproduced exactly: every tap's difference is 0, and the pixel
  // is the nearest sample's colour, which the shortcut writes directly.
  const size_t nearest_pixel = static_cast<size_t>(std::lround(sy)) * in.width + std::lround(sx);
  const size_t nearest = nearest_pixel * 3;
  bool uniform = true;
  for (int y = y0; y <= y1 && uniform; ++y) {
    const size_t first = static_cast<size_t>(y) * in.width + x0;
    uniform = run[first] >= static_cast<uint32_t>(x1 - x0 + 1) && same(first, nearest_pixel);
  }
  if (uniform) {
    for (int c = 0; c < 3; ++c) out.rgb[i * 3 + c] = static_cast<float>(std::max(0.0, double{in.rgb[nearest + c]}));
    return;
  }
  thread_local std::vector<double> wx, wy;
  wx.resize(static_cast<size_t>(x1 - x0 + 1));
  wy.resize(static_cast<size_t>(y1 - y0 + 1));
  double sum_x = 0.0, sum_y = 0.0;
  for (int x = x0; x <= x1; ++x) sum_x += wx[x - x0] = Lanczos((x - sx) / scx);
  for (int y = y0; y <= y1; ++y) sum_y += wy[y - y0] = Lanczos((y - sy) / scy);
  double acc[3] = {0.0, 0.0, 0.0};
  for (int y = y0; y <= y1; ++y) {
    const float* row = &in.rgb[static_cast<size_t>(y) * in.width * 3];
    double row_acc[3] = {0.0, 0.0, 0.0};
    for (int x = x0; x <= x1; ++x) {
      const double w = wx[x - x0];
      for (int c = 0; c < 3; ++c) row_acc[c] += w * (row[x * 3 + c] - in.rgb[nearest + c]);
    }
    for (int c = 0; c < 3; ++c) acc[c] += wy[y - y0] * row_acc[c];
  }
  const double norm = 1.0 / (sum_x * sum_y);
  for (int c = 0; c < 3; ++c) {
    // Lanczos lobes can undershoot next to a bright edge; light is not negative.
    out.rgb[i * 3 + c] = static_cast<float>(std::max(0.0, in.rgb[nearest + c] + acc[c] * norm));
  }
}

GroundTruthImage LensResampler::ResampleTruth(const GroundTruthImage& in) const {
  if (in.width != pinhole_.width_px || in.height != pinhole_.height_px) {
    throw Error("lens resampling: pinhole truth image has the wrong size");
  }
  GroundTruthImage out;
  out.width = width_;
  out.height = height_;
  out.depth_m.resize(source_x_.size());
  out.object_id.resize(source_x_.size());
  for (size_t i = 0; i < source_x_.size(); ++i) {
    const size_t nearest = static_cast<size_t>(std::lround(source_y_[i])) * in.width + std::lround(source_x_[i]);
    out.depth_m[i] = in.depth_m[nearest];
    out.object_id[i] = in.object_id[nearest];
  }
  return out;
}

}  // namespace aar
