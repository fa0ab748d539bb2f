#include "aar/renderer/msaa.h"

#include <algorithm>

#include "aar/error.h"

namespace aar {
namespace {

int BitReverse(int value, int count) {
  int bits = 0;
  while ((1 << bits) < count) ++bits;
  int reversed = 0;
  for (int b = 0; b < bits; ++b) {
    if (value & (1 << b)) reversed |= 1 << (bits - 1 - b);
  }
  return reversed;
}

}  // namespace

bool IsSupportedMsaaLevel(int level) { return level == 1 || level == 4 || level == 8 || level == 16 || level == 32; }

std::vector<Vec2> StandardSampleLocations(int samples) {
  auto sixteenths = [](std::vector<std::pair<int, int>> p) {
    std::vector<Vec2> out;
    for (const auto& [x, y] : p) out.push_back({x / 16.0, y / 16.0});
    return out;
  };
  switch (samples) {
    case 1:
      return {{0.5, 0.5}};
    case 2:
      return sixteenths({{12, 12}, {4, 4}});
    case 4:
      return sixteenths({{6, 2}, {14, 6}, {2, 10}, {10, 14}});
    case 8:
      return sixteenths({{9, 5}, {7, 11}, {13, 9}, {5, 3}, {3, 13}, {1, 7}, {11, 15}, {15, 1}});
    case 16:
      return sixteenths({{9, 9},
                         {7, 5},
                         {5, 10},
                         {12, 7},
                         {3, 6},
                         {10, 13},
                         {13, 11},
                         {11, 3},
                         {6, 14},
                         {8, 1},
                         {4, 2},
                         {2, 12},
                         {0, 8},
                         {15, 4},
                         {14, 15},
                         {1, 0}});
    default:
      throw Error("no standard sample locations for " + std::to_string(samples) + " samples");
  }
}

void CheckMsaaLevel(int level) {
  if (!IsSupportedMsaaLevel(level)) {
    throw Error("--msaa " + std::to_string(level) + ": unknown MSAA level (use 1, 4, 8, 16 or 32)");
  }
}

MsaaPlan PlanMsaa(int level, const std::vector<int>& native_counts) {
  CheckMsaaLevel(level);
  MsaaPlan plan;
  plan.level = level;
  if (std::find(native_counts.begin(), native_counts.end(), level) != native_counts.end()) {
    plan.native_samples = level;
    plan.passes = 1;
    plan.offsets_px = {{0.0, 0.0}};
    plan.method = "native";
    return plan;
  }
  int n = 1;
  for (int c : native_counts) {
    if (c > n && level % c == 0 && c <= 16) n = c;
  }
  const int k = level / n;
  plan.native_samples = n;
  plan.passes = k;
  plan.method = "composed";
  // Cell size of the native n-rooks grid is 1/n pixel (for n = 1 the cell is the pixel).
  const double cell = 1.0 / n;
  for (int j = 0; j < k; ++j) {
    const double sigma = j;
    const double tau = BitReverse(j, k);
    plan.offsets_px.push_back({((sigma + 0.5) / k - 0.5) * cell, ((tau + 0.5) / k - 0.5) * cell});
  }
  return plan;
}

std::vector<Vec2> CompositeSamplePattern(const MsaaPlan& plan) {
  const std::vector<Vec2> base = StandardSampleLocations(plan.native_samples);
  std::vector<Vec2> pattern;
  for (const Vec2& offset : plan.offsets_px) {
    for (const Vec2& s : base) pattern.push_back({s.x + offset.x, s.y + offset.y});
  }
  return pattern;
}

}  // namespace aar
