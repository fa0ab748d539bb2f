// The sun's position (solar_position.h) against published values and
// geometry that cannot be otherwise.

#include "aar/solar_position.h"

#include <gtest/gtest.h>

#include "../test_support.h"

namespace aar {
namespace {

// NREL's Solar Position Algorithm example (Reda and Andreas 2004, table A4.1):
// 17 October 2003, 12:30:30 local time at UTC-7, 39.742476 N, 105.1786 W:
// topocentric zenith 50.11162 deg (refraction at 820 mbar, 11 C), azimuth
// 194.34024 deg east of north. NOAA's algorithm holds it to about 0.01 deg;
// its refraction (standard atmosphere) differs from SPA's there by 0.003 deg.
TEST(SolarPosition, AgreesWithTheSolarPositionAlgorithmsExample) {
  const SolarPosition p = SunPosition(ParseUtcTime("2003-10-17T19:30:30Z", "time"), 39.742476, -105.1786);
  EXPECT_NEAR(p.elevation_deg, 90.0 - 50.11162, 0.05);
  EXPECT_NEAR(p.azimuth_deg, 194.34024, 0.05);
}

TEST(SolarPosition, FollowsTheSeasonsAndTheDay) {
  // June solstice: overhead on the Tropic of Cancer at local solar noon
  // (12:00 UTC at 0 deg, less the equation of time, about -1.8 min).
  const SolarPosition solstice = SunPosition(ParseUtcTime("2026-06-21T12:02:00Z", "time"), 23.44, 0.0);
  EXPECT_GT(solstice.elevation_deg, 89.5);
  // December midnight at 50 N on the Greenwich meridian: deep below the horizon, due north.
  const SolarPosition midnight = SunPosition(ParseUtcTime("2026-12-21T00:00:00Z", "time"), 50.0, 0.0);
  EXPECT_NEAR(midnight.elevation_deg, -(90.0 - 50.0 + 23.44), 0.3);
  EXPECT_TRUE(midnight.azimuth_deg < 2.0 || midnight.azimuth_deg > 358.0) << midnight.azimuth_deg;
  // Morning sun in the east, afternoon sun in the west (45 N, equinox).
  EXPECT_NEAR(SunPosition(ParseUtcTime("2026-03-20T08:00:00Z", "time"), 45.0, 0.0).azimuth_deg, 115.0, 15.0);
  EXPECT_NEAR(SunPosition(ParseUtcTime("2026-03-20T16:00:00Z", "time"), 45.0, 0.0).azimuth_deg, 245.0, 15.0);
}

TEST(SolarPosition, RefusesTimesItCannotRead) {
  for (const char* text : {"2026-12-06 14:30Z", "2026-12-06T14:30", "2026-02-30T10:00Z", "2026-12-06T24:00Z",
                           "1800-01-01T00:00Z", "2026-12-06T14:30:61Z", "2026-12-06T14:30:00+01:00"}) {
    SCOPED_TRACE(text);
    const std::string error = test::ErrorOf([&] { ParseUtcTime(text, "--sun-time"); });
    EXPECT_NE(error.find("--sun-time '"), std::string::npos) << error;
  }
  const UtcTime t = ParseUtcTime("2026-12-06T14:30:15.5Z", "--sun-time");
  EXPECT_EQ(t.hour, 14);
  EXPECT_EQ(t.minute, 30);
  EXPECT_EQ(t.second, 15.5);
}

}  // namespace
}  // namespace aar
