// Blooming and smear (renderer/charge_spill.h): the charge a saturated
// pixel spills goes along its column only, fills each neighbour to the
// full well, is conserved but for what the drain takes and what passes the
// image's edge; the smear adds its fraction of the column's mean; both off
// changes nothing; through the sensor model a bright spot streaks its
// column by the number of wells its excess fills.

#include "aar/renderer/charge_spill.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

#include "aar/renderer/sensor_model.h"

namespace aar {
namespace {

constexpr double kWell = 1000.0;

double Sum(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

TEST(ChargeSpill, OffChangesNothing) {
  std::vector<double> e = {0.0, 5.0 * kWell, 0.3 * kWell, 2.0 * kWell, 7.0, 0.0};
  const std::vector<double> before = e;
  SpillCharge(e, 2, 3, 1, ChargeSpillOptions{kWell, 0.0, 0.0});
  EXPECT_EQ(e, before);
}

// One pixel holding 10 wells in the middle of a 21-row column, blooming
// 0.5: it keeps one well, 4.5 wells spill, 2.25 each way: two neighbours
// full and a quarter well in the third, on either side; the other column
// and the drain's half are untouched.
TEST(ChargeSpill, BloomingFillsTheColumnsWellsBothWaysAndConservesCharge) {
  const int width = 2, height = 21, row = 10;
  std::vector<double> e(width * height, 0.0);
  e[row * width + 1] = 10.0 * kWell;
  SpillCharge(e, width, height, 1, ChargeSpillOptions{kWell, 0.5, 0.0});
  for (int y = 0; y < height; ++y) {
    EXPECT_EQ(e[y * width + 0], 0.0) << "row " << y;  // the neighbouring column: nothing
    const int d = std::abs(y - row);
    const double expected = d <= 2 ? kWell : d == 3 ? 0.25 * kWell : 0.0;
    EXPECT_NEAR(e[y * width + 1], expected, 1e-9) << "row " << y;
  }
  EXPECT_NEAR(Sum(e), kWell + 0.5 * 9.0 * kWell, 1e-9);
}

// At the top row the upward half leaves the image; two saturated pixels'
// spill pass each other's full wells and add up beyond.
TEST(ChargeSpill, BloomingLosesWhatPassesTheEdgeAndCascadesThroughFullWells) {
  std::vector<double> top(8, 0.0);
  top[0] = 3.0 * kWell;
  SpillCharge(top, 1, 8, 1, ChargeSpillOptions{kWell, 1.0, 0.0});
  EXPECT_NEAR(top[0], kWell, 1e-9);
  EXPECT_NEAR(top[1], kWell, 1e-9);  // half of two wells down, half lost above
  EXPECT_NEAR(Sum(top), 2.0 * kWell, 1e-9);

  std::vector<double> pair(12, 0.0);
  pair[5] = 3.0 * kWell;  // 2 wells excess: 1 up, 1 down
  pair[6] = 3.0 * kWell;  // the same
  SpillCharge(pair, 1, 12, 1, ChargeSpillOptions{kWell, 1.0, 0.0});
  // Pixel 5's downward well passes 6 (full) and joins 6's own: 7 and 8 fill;
  // upwards the same: 4 and 3.
  const std::vector<double> expected = {0, 0, 0, kWell, kWell, kWell, kWell, kWell, kWell, 0, 0, 0};
  for (size_t y = 0; y < pair.size(); ++y) EXPECT_NEAR(pair[y], expected[y], 1e-9) << "row " << y;
  EXPECT_NEAR(Sum(pair), 6.0 * kWell, 1e-9);  // 2 wells kept + 4 spilled
}

// Smear: every pixel of a column gains the smear times the column's mean;
// each channel of an interleaved image is its own column.
TEST(ChargeSpill, SmearAddsItsFractionOfTheColumnMeanPerChannel) {
  const int width = 3, height = 10, channels = 3;
  std::vector<double> e(width * height * channels, 10.0);
  e[(4 * width + 1) * channels + 2] = 10.0 + 500.0;  // column 1, blue
  SpillCharge(e, width, height, channels, ChargeSpillOptions{1e9, 0.0, 0.02});
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < channels; ++c) {
        const bool bright_column = x == 1 && c == 2;
        const double base = (bright_column && y == 4) ? 510.0 : 10.0;
        const double mean = bright_column ? 10.0 + 500.0 / height : 10.0;
        EXPECT_NEAR(e[(y * width + x) * channels + c], base + 0.02 * mean, 1e-9) << x << "," << y << "," << c;
      }
    }
  }
}

// Through the sensor model: one pixel at radiance 20 over a dark frame
// (exposure 5,000 e- per unit, full well 10,000: 10 wells, 9 in excess),
// blooming 1: 4.5 wells each way, so 4 full neighbours above and below
// (reading the full well, radiance 2, less its shot noise of 0.02 that the
// well clips on one side), a fifth at half; the pixels beside it in its
// row stay dark.
TEST(ChargeSpill, SensorModelStreaksABrightSpotAlongItsColumn) {
  SensorParams sensor;
  sensor.read_noise_e = 0.0;
  sensor.dsnu_e = 0.0;
  sensor.prnu = 0.0;
  sensor.blooming = 1.0;
  LinearImage radiance;
  radiance.width = 15;
  radiance.height = 15;
  radiance.rgb.assign(15 * 15 * 3, 0.0f);
  for (int c = 0; c < 3; ++c) radiance.rgb[(7 * 15 + 7) * 3 + c] = 20.0f;
  const LinearImage out = ApplySensorModel(radiance, sensor, SensorExposure{});
  const auto at = [&](int x, int y) { return out.rgb[(y * 15 + x) * 3 + 1]; };
  int full = 0;
  for (int y = 0; y < 15; ++y) full += at(7, y) >= 1.9f ? 1 : 0;
  EXPECT_EQ(full, 9);
  EXPECT_NEAR(at(7, 2), 1.0, 0.05);  // half a well, with its shot noise (sigma 0.014)
  EXPECT_NEAR(at(7, 12), 1.0, 0.05);
  EXPECT_LT(at(6, 7), 0.01f);
  EXPECT_LT(at(8, 7), 0.01f);
  sensor.blooming = 0.0;
  const LinearImage drained = ApplySensorModel(radiance, sensor, SensorExposure{});
  EXPECT_LT(drained.rgb[(6 * 15 + 7) * 3 + 1], 0.01f);
}

}  // namespace
}  // namespace aar
