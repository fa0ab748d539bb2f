// Procedural texture building blocks: an 8-bit RGB image with colour
// quantisation, lattice value noise, a 5x7 block font, an atlas packer and the
// baking loop that evaluates a paint function for every texel of a patch.
#pragma once

#include <cstdint>
#include <functional>
#include <string_view>
#include <vector>

#include "geometry.h"

namespace aar::scenes {

/// Linear-ish display colour, channels in [0, 1].
using Color = Vec3;

/// 8-bit RGB image; colours are quantised to `levels` values per channel
/// when stored (fewer levels -> smaller PNG).
class RgbImage {
 public:
  RgbImage(int width, int height, int levels);
  int width() const { return width_; }
  int height() const { return height_; }
  void Set(int x, int y, const Color& c);
  const std::vector<std::uint8_t>& pixels() const { return pixels_; }

 private:
  int width_, height_, levels_;
  std::vector<std::uint8_t> pixels_;
};

/// Deterministic 64-bit hash of integer coordinates (splitmix64 finaliser).
std::uint64_t Hash64(std::uint64_t seed, std::int64_t a, std::int64_t b = 0, std::int64_t c = 0);
/// Hash64 mapped to [0, 1).
double Hash01(std::uint64_t seed, std::int64_t a, std::int64_t b = 0, std::int64_t c = 0);

/// 3-D value noise on the unit integer lattice with quintic interpolation,
/// values in [-1, 1]. Each instance (seed) is an independent field.
class ValueNoise {
 public:
  explicit ValueNoise(std::uint64_t seed) : seed_(seed) {}
  double operator()(const Vec3& p) const;

 private:
  std::uint64_t seed_;
};

/// Whether (x, y) falls on ink of `text` set in a 5x7 block font; (x, y) in
/// metres relative to the centre of the text box, x to the reader's right, y
/// up; `height` = cap height. Supports A-Z, 0-9, '.', '-', ' '.
bool TextInk(std::string_view text, double x, double y, double height);

/// Inside a rounded rectangle centred at (0, 0) with half sizes (hx, hy) and corner radius r.
bool InRoundedRect(double x, double y, double hx, double hy, double r);

/// Distance from `x` to the nearest multiple of `spacing` (offset by `phase`).
double DistanceToGrid(double x, double spacing, double phase = 0.0);

/// Shelf-packs one rectangle per patch (texel size = arc lengths times a
/// common density) into a width x height atlas, with `gutter` texels around
/// each, choosing the largest common density that fits.
struct AtlasLayout {
  double texels_per_m = 0;
  std::vector<AtlasRect> rects;  ///< one per input patch, same order
};
AtlasLayout PackAtlas(const std::vector<const Patch*>& patches, int width, int height, int gutter);

/// Colour of a patch at texture parameters (u, v).
using PaintFn = std::function<Color(double u, double v)>;

/// Fills the patch's rectangle plus `gutter` texels around it by evaluating
/// `paint` at texel centres (u, v clamped at the edges, wrapped if periodic).
/// Runs on all hardware threads; `paint` must be thread-safe (pure).
void Bake(RgbImage& image, const AtlasRect& rect, int gutter, bool periodic_v, const PaintFn& paint);

}  // namespace aar::scenes
