#include "texture_synth.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <thread>

namespace aar::scenes {

RgbImage::RgbImage(int width, int height, int levels)
    : width_(width),
      height_(height),
      levels_(levels),
      pixels_(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3, 0) {}

void RgbImage::Set(int x, int y, const Color& c) {
  const std::size_t at =
      (static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x)) * 3;
  for (int k = 0; k < 3; ++k) {
    const double q = std::round(std::clamp(c[k], 0.0, 1.0) * (levels_ - 1)) / (levels_ - 1);
    pixels_[at + static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(std::lround(q * 255.0));
  }
}

std::uint64_t Hash64(std::uint64_t seed, std::int64_t a, std::int64_t b, std::int64_t c) {
  auto mix = [](std::uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  };
  std::uint64_t h = mix(seed + 0x9e3779b97f4a7c15ULL);
  h = mix(h ^ static_cast<std::uint64_t>(a));
  h = mix(h ^ static_cast<std::uint64_t>(b));
  return mix(h ^ static_cast<std::uint64_t>(c));
}

double Hash01(std::uint64_t seed, std::int64_t a, std::int64_t b, std::int64_t c) {
  return static_cast<double>(Hash64(seed, a, b, c) >> 11) * 0x1.0p-53;
}

double ValueNoise::operator()(const Vec3& p) const {
  const double fx = std::floor(p.x()), fy = std::floor(p.y()), fz = std::floor(p.z());
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy), iz = static_cast<std::int64_t>(fz);
  auto fade = [](double t) { return t * t * t * (t * (t * 6 - 15) + 10); };
  const double tx = fade(p.x() - fx), ty = fade(p.y() - fy), tz = fade(p.z() - fz);
  auto lattice = [&](std::int64_t dx, std::int64_t dy, std::int64_t dz) {
    return 2.0 * Hash01(seed_, ix + dx, iy + dy, iz + dz) - 1.0;
  };
  auto lerp = [](double a, double b, double t) { return a + (b - a) * t; };
  const double x00 = lerp(lattice(0, 0, 0), lattice(1, 0, 0), tx);
  const double x10 = lerp(lattice(0, 1, 0), lattice(1, 1, 0), tx);
  const double x01 = lerp(lattice(0, 0, 1), lattice(1, 0, 1), tx);
  const double x11 = lerp(lattice(0, 1, 1), lattice(1, 1, 1), tx);
  return lerp(lerp(x00, x10, ty), lerp(x01, x11, ty), tz);
}

namespace {

struct Glyph {
  char c;
  std::array<const char*, 7> rows;
};

// 5x7 block capitals; '#' = ink.
constexpr Glyph kFont[] = {
    {'A', {".###.", "#...#", "#...#", "#####", "#...#", "#...#", "#...#"}},
    {'B', {"####.", "#...#", "#...#", "####.", "#...#", "#...#", "####."}},
    {'C', {".###.", "#...#", "#....", "#....", "#....", "#...#", ".###."}},
    {'D', {"####.", "#...#", "#...#", "#...#", "#...#", "#...#", "####."}},
    {'E', {"#####", "#....", "#....", "####.", "#....", "#....", "#####"}},
    {'F', {"#####", "#....", "#....", "####.", "#....", "#....", "#...."}},
    {'G', {".###.", "#...#", "#....", "#.###", "#...#", "#...#", ".####"}},
    {'H', {"#...#", "#...#", "#...#", "#####", "#...#", "#...#", "#...#"}},
    {'I', {".###.", "..#..", "..#..", "..#..", "..#..", "..#..", ".###."}},
    {'J', {"..###", "...#.", "...#.", "...#.", "...#.", "#..#.", ".##.."}},
    {'K', {"#...#", "#..#.", "#.#..", "##...", "#.#..", "#..#.", "#...#"}},
    {'L', {"#....", "#....", "#....", "#....", "#....", "#....", "#####"}},
    {'M', {"#...#", "##.##", "#.#.#", "#.#.#", "#...#", "#...#", "#...#"}},
    {'N', {"#...#", "##..#", "#.#.#", "#..##", "#...#", "#...#", "#...#"}},
    {'O', {".###.", "#...#", "#...#", "#...#", "#...#", "#...#", ".###."}},
    {'P', {"####.", "#...#", "#...#", "####.", "#....", "#....", "#...."}},
    {'Q', {".###.", "#...#", "#...#", "#...#", "#.#.#", "#..#.", ".##.#"}},
    {'R', {"####.", "#...#", "#...#", "####.", "#.#..", "#..#.", "#...#"}},
    {'S', {".####", "#....", "#....", ".###.", "....#", "....#", "####."}},
    {'T', {"#####", "..#..", "..#..", "..#..", "..#..", "..#..", "..#.."}},
    {'U', {"#...#", "#...#", "#...#", "#...#", "#...#", "#...#", ".###."}},
    {'V', {"#...#", "#...#", "#...#", "#...#", "#...#", ".#.#.", "..#.."}},
    {'W', {"#...#", "#...#", "#...#", "#.#.#", "#.#.#", "#.#.#", ".#.#."}},
    {'X', {"#...#", "#...#", ".#.#.", "..#..", ".#.#.", "#...#", "#...#"}},
    {'Y', {"#...#", "#...#", ".#.#.", "..#..", "..#..", "..#..", "..#.."}},
    {'Z', {"#####", "....#", "...#.", "..#..", ".#...", "#....", "#####"}},
    {'0', {".###.", "#...#", "#..##", "#.#.#", "##..#", "#...#", ".###."}},
    {'1', {"..#..", ".##..", "..#..", "..#..", "..#..", "..#..", ".###."}},
    {'2', {".###.", "#...#", "....#", "...#.", "..#..", ".#...", "#####"}},
    {'3', {"####.", "....#", "....#", ".###.", "....#", "....#", "####."}},
    {'4', {"...#.", "..##.", ".#.#.", "#..#.", "#####", "...#.", "...#."}},
    {'5', {"#####", "#....", "####.", "....#", "....#", "#...#", ".###."}},
    {'6', {".###.", "#....", "#....", "####.", "#...#", "#...#", ".###."}},
    {'7', {"#####", "....#", "...#.", "..#..", ".#...", ".#...", ".#..."}},
    {'8', {".###.", "#...#", "#...#", ".###.", "#...#", "#...#", ".###."}},
    {'9', {".###.", "#...#", "#...#", ".####", "....#", "....#", ".###."}},
    {'.', {".....", ".....", ".....", ".....", ".....", ".##..", ".##.."}},
    {'-', {".....", ".....", ".....", ".###.", ".....", ".....", "....."}},
};

const Glyph* FindGlyph(char c) {
  for (const Glyph& g : kFont) {
    if (g.c == c) return &g;
  }
  return nullptr;  // space and unsupported characters draw nothing
}

}  // namespace

bool TextInk(std::string_view text, double x, double y, double height) {
  const double unit = height / 7.0;
  const double width = (6.0 * static_cast<double>(text.size()) - 1.0) * unit;
  const double cx = (x + 0.5 * width) / unit, cy = (0.5 * height - y) / unit;
  if (cx < 0 || cy < 0 || cx >= width / unit || cy >= 7.0) return false;
  const auto col = static_cast<std::size_t>(cx), row = static_cast<std::size_t>(cy);
  const std::size_t in_cell = col % 6;
  if (in_cell == 5) return false;  // letter spacing
  const Glyph* g = FindGlyph(text[col / 6]);
  return g != nullptr && g->rows[row][in_cell] == '#';
}

bool InRoundedRect(double x, double y, double hx, double hy, double r) {
  const double dx = std::abs(x) - (hx - r), dy = std::abs(y) - (hy - r);
  if (dx > r || dy > r) return false;
  if (dx <= 0 || dy <= 0) return true;
  return dx * dx + dy * dy <= r * r;
}

double DistanceToGrid(double x, double spacing, double phase) {
  const double t = (x - phase) / spacing;
  return std::abs(t - std::round(t)) * spacing;
}

AtlasLayout PackAtlas(const std::vector<const Patch*>& patches, int width, int height, int gutter) {
  // Tallest first (stable), left to right on shelves.
  std::vector<std::size_t> order(patches.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return patches[a]->length_v_m > patches[b]->length_v_m; });
  auto try_pack = [&](double density, std::vector<AtlasRect>* out) {
    int x = 0, y = 0, shelf = 0;
    for (std::size_t i : order) {
      const int w = static_cast<int>(std::ceil(patches[i]->length_u_m * density)) + 2 * gutter;
      const int h = static_cast<int>(std::ceil(patches[i]->length_v_m * density)) + 2 * gutter;
      if (w > width) return false;
      if (x + w > width) {
        x = 0;
        y += shelf;
        shelf = 0;
      }
      if (y + h > height) return false;
      if (out != nullptr) {
        (*out)[i] = AtlasRect{static_cast<double>(x + gutter),
                              static_cast<double>(y + gutter),
                              static_cast<double>(w - 2 * gutter),
                              static_cast<double>(h - 2 * gutter),
                              width,
                              height};
      }
      x += w;
      shelf = std::max(shelf, h);
    }
    return true;
  };
  // Largest density that fits, to 0.1 texel per metre.
  double lo = 1.0, hi = 4096.0;
  while (hi - lo > 0.1) {
    const double mid = 0.5 * (lo + hi);
    (try_pack(mid, nullptr) ? lo : hi) = mid;
  }
  AtlasLayout layout;
  layout.texels_per_m = std::floor(lo * 10.0) / 10.0;
  layout.rects.resize(patches.size());
  try_pack(layout.texels_per_m, &layout.rects);
  return layout;
}

void Bake(RgbImage& image, const AtlasRect& rect, int gutter, bool periodic_v, const PaintFn& paint) {
  const int x_begin = std::max(0, static_cast<int>(rect.x0) - gutter);
  const int x_end = std::min(image.width(), static_cast<int>(rect.x0 + rect.width) + gutter);
  const int y_begin = std::max(0, static_cast<int>(rect.y0) - gutter);
  const int y_end = std::min(image.height(), static_cast<int>(rect.y0 + rect.height) + gutter);
  // Rows are independent (each texel depends only on its own (u, v)), so
  // interleaved rows on several threads give the same image as one thread.
  auto bake_rows = [&](int first, int step) {
    for (int y = y_begin + first; y < y_end; y += step) {
      double v = (y + 0.5 - rect.y0) / rect.height;
      v = periodic_v ? v - std::floor(v) : std::clamp(v, 0.0, 1.0);
      for (int x = x_begin; x < x_end; ++x) {
        const double u = std::clamp((x + 0.5 - rect.x0) / rect.width, 0.0, 1.0);
        image.Set(x, y, paint(u, v));
      }
    }
  };
  const int threads = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 32u));
  std::vector<std::jthread> workers;
  for (int t = 1; t < threads; ++t) workers.emplace_back(bake_rows, t, threads);
  bake_rows(0, threads);
}

}  // namespace aar::scenes
