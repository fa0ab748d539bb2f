#include "aar/renderer/background_texture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "aar/error.h"

namespace aar {
namespace {

// A 32-bit integer hash (lowbias32, Chris Wellons) of a lattice point and a stream.
uint32_t Hash(uint32_t x, uint32_t y, uint32_t stream) {
  uint32_t h = x * 0x8da6b343u ^ y * 0xd8163841u ^ stream * 0xcb1ab31fu;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return h;
}

float Unit(uint32_t h) { return static_cast<float>(h >> 8) * (1.0f / 16777216.0f); }  // [0, 1)

// Periodic value noise in [0, 1]: lattice spacing `cell` texels on a tile of
// `size` texels (cell divides size), smoothstep interpolation.
float ValueNoise(int x, int y, int cell, int size, uint32_t stream) {
  const int period = size / cell;
  const int cx = x / cell, cy = y / cell;
  const float fx = static_cast<float>(x % cell) / static_cast<float>(cell);
  const float fy = static_cast<float>(y % cell) / static_cast<float>(cell);
  auto at = [&](int i, int j) {
    return Unit(Hash(static_cast<uint32_t>(i % period), static_cast<uint32_t>(j % period), stream));
  };
  const float sx = fx * fx * (3.0f - 2.0f * fx), sy = fy * fy * (3.0f - 2.0f * fy);
  const float top = at(cx, cy) + sx * (at(cx + 1, cy) - at(cx, cy));
  const float bottom = at(cx, cy + 1) + sx * (at(cx + 1, cy + 1) - at(cx, cy + 1));
  return top + sy * (bottom - top);
}

// Octaves from `largest` down to 2 texels, amplitude halving, normalised to [0, 1].
float Fractal(int x, int y, int largest, int size, uint32_t stream) {
  float sum = 0.0f, weight = 0.0f, amplitude = 1.0f;
  for (int cell = largest; cell >= 2; cell /= 2) {
    sum += amplitude * ValueNoise(x, y, cell, size, stream + static_cast<uint32_t>(cell));
    weight += amplitude;
    amplitude *= 0.5f;
  }
  return sum / weight;
}

using Rgb = std::array<float, 3>;  // sRGB, 0-255

Rgb Scale(const Rgb& c, float f) { return {c[0] * f, c[1] * f, c[2] * f}; }
Rgb Mix(const Rgb& a, const Rgb& b, float t) {
  return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]), a[2] + t * (b[2] - a[2])};
}

void CheckSize(int size, const char* what) {
  if (size < 256 || (size & (size - 1)) != 0) {
    throw Error(std::string(what) + " texture size " + std::to_string(size) + ": expected a power of two >= 256");
  }
}

TextureMips Finish(const std::vector<Rgb>& pixels, int size) {
  std::vector<uint8_t> rgba(pixels.size() * 4);
  for (size_t i = 0; i < pixels.size(); ++i) {
    for (int c = 0; c < 3; ++c) rgba[i * 4 + c] = static_cast<uint8_t>(std::clamp(std::lround(pixels[i][c]), 0L, 255L));
    rgba[i * 4 + 3] = 255;
  }
  return BuildMips(std::move(rgba), size, size);
}

// Crops (sRGB): pasture, young and ripe grain, maize, bare soil, stubble.
constexpr Rgb kCrops[] = {{88, 118, 52}, {112, 138, 58},  {176, 160, 92}, {74, 104, 44},
                          {122, 96, 70}, {156, 140, 104}, {98, 110, 60},  {140, 116, 82}};
constexpr Rgb kForest = {46, 66, 38};
constexpr Rgb kWater = {32, 52, 64};
constexpr Rgb kRoad = {104, 102, 98};
constexpr Rgb kHedge = {58, 74, 42};

constexpr int kBlock = 256;  // road grid [texels]

// The parcel of texel (x, y) inside its block: rows of 24-96 texels, each cut
// into parcels of 32-128 texels; returns a parcel id and whether the texel is
// on a parcel edge (hedge).
struct Parcel {
  uint32_t id = 0;
  bool edge = false;
  bool rows_along_x = false;
};

Parcel ParcelAt(int x, int y, uint32_t seed) {
  const int bx = x / kBlock, by = y / kBlock;
  const int lx = x % kBlock, ly = y % kBlock;
  const uint32_t block = Hash(static_cast<uint32_t>(bx), static_cast<uint32_t>(by), seed ^ 0x51u);
  const bool transpose = (block & 1u) != 0;  // rows along x or along y
  const int a = transpose ? lx : ly;         // across the rows
  const int b = transpose ? ly : lx;         // along a row
  int row_start = 0, row = 0, row_end = 0;
  while (true) {
    const int h = 24 + static_cast<int>(Hash(block, static_cast<uint32_t>(row), 7u) % 73u);
    row_end = std::min(kBlock, row_start + h);
    if (a < row_end || row_end == kBlock) break;
    row_start = row_end;
    ++row;
  }
  int start = 0, k = 0, end = 0;
  while (true) {
    const int w = 32 + static_cast<int>(Hash(block, static_cast<uint32_t>(row * 64 + k), 11u) % 97u);
    end = std::min(kBlock, start + w);
    if (b < end || end == kBlock) break;
    start = end;
    ++k;
  }
  Parcel p;
  p.id = Hash(block, static_cast<uint32_t>(row * 64 + k), 13u);
  p.edge = a == row_start || b == start;
  p.rows_along_x = ((p.id >> 3) & 1u) != 0;
  return p;
}

}  // namespace

TextureMips TerrainTexture(uint32_t seed, int size) {
  CheckSize(size, "terrain");
  std::vector<Rgb> pixels(static_cast<size_t>(size) * size);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const Parcel parcel = ParcelAt(x, y, seed);
      const Rgb crop = kCrops[parcel.id % std::size(kCrops)];
      const float detail = Fractal(x, y, 16, size, seed ^ 0x1000u);
      // Plough rows: a period of 2-4 texels along the parcel's direction.
      const int period = 2 + static_cast<int>((parcel.id >> 8) % 3u);
      const int along = parcel.rows_along_x ? y : x;
      const float rows = (along % period == 0) ? 0.93f : 1.0f;
      const float tone = 0.9f + 0.2f * Unit(Hash(parcel.id, 0u, 17u));
      Rgb c = Scale(crop, tone * rows * (0.9f + 0.2f * detail));
      if (parcel.edge) c = Mix(c, kHedge, 0.7f);

      // Forest patches where a low-frequency noise is high.
      const float woods = Fractal(x, y, 128, size, seed ^ 0x2000u);
      if (woods > 0.62f) c = Scale(kForest, 0.8f + 0.4f * Fractal(x, y, 8, size, seed ^ 0x2100u));

      // Roads on the block grid (some blocks' edges left out) and a winding highway.
      const int bx = x / kBlock, by = y / kBlock;
      const bool road_x =
          y % kBlock == 0 && Hash(static_cast<uint32_t>(bx), static_cast<uint32_t>(by), seed ^ 0x3000u) % 4u != 0u;
      const bool road_y =
          x % kBlock == 0 && Hash(static_cast<uint32_t>(bx), static_cast<uint32_t>(by), seed ^ 0x3100u) % 4u != 0u;
      const double phase = 6.283185307179586 * static_cast<double>(x) / size;
      const double centre = size * (0.3 + 0.05 * std::sin(2.0 * phase + (seed % 7u)) + 0.03 * std::sin(5.0 * phase));
      const bool highway = std::abs(static_cast<double>(y) - centre) < 1.0;
      if (road_x || road_y || highway) c = Scale(kRoad, 0.95f + 0.1f * detail);

      // Lakes (low-frequency noise low) and a river (a level line of a smooth noise).
      const float lakes = 0.65f * ValueNoise(x, y, size / 8, size, seed ^ 0x4000u) +
                          0.35f * ValueNoise(x, y, size / 32, size, seed ^ 0x4100u);
      const float river = ValueNoise(x, y, size / 4, size, seed ^ 0x5000u);
      if (lakes < 0.2f || std::abs(river - 0.5f) < 0.004f) c = Scale(kWater, 0.92f + 0.16f * detail);
      pixels[static_cast<size_t>(y) * size + x] = c;
    }
  }
  return Finish(pixels, size);
}

TextureMips CloudTexture(uint32_t seed, int size) {
  CheckSize(size, "cloud");
  std::vector<Rgb> pixels(static_cast<size_t>(size) * size);
  constexpr Rgb kTop = {246, 248, 252};
  constexpr Rgb kShade = {168, 176, 192};
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      // Billows: 1 - |2n - 1| turns the noise's middle values into bright ridges.
      const float n = Fractal(x, y, 128, size, seed ^ 0x6000u);
      const float billow = 1.0f - std::abs(2.0f * n - 1.0f);
      const float large = Fractal(x, y, 256, size, seed ^ 0x7000u);
      const float t = std::clamp(0.15f + 0.9f * billow * (0.6f + 0.6f * large), 0.0f, 1.0f);
      pixels[static_cast<size_t>(y) * size + x] = Mix(kShade, kTop, t);
    }
  }
  return Finish(pixels, size);
}

}  // namespace aar
