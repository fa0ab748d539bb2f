#pragma once
// Where the sun is: its azimuth and elevation seen from a place on the Earth
// at a moment in UTC, by NOAA's solar calculator (after Meeus, Astronomical
// Algorithms, 1991): geometric mean longitude and anomaly of the sun, the
// equation of centre, apparent longitude, the obliquity of the ecliptic
// corrected for nutation, the declination and the equation of time, then the
// hour angle of the true solar time and the standard atmospheric refraction
// (NOAA's piecewise fit). NOAA gives it as accurate to about 0.01 deg for
// dates between 1901 and 2099; the test holds it within 0.05 deg of NREL's
// Solar Position Algorithm example (Reda and Andreas 2004, NREL/TP-560-34302).

#include <string>

namespace aar {

/// A moment in UTC.
struct UtcTime {
  int year = 2000, month = 1, day = 1, hour = 12, minute = 0;
  double second = 0.0;
};

/// Parses "YYYY-MM-DDTHH:MM[:SS[.s]]Z" (ISO 8601 in UTC; the Z is
/// required); throws aar::Error naming `what` (a flag) and the text otherwise,
/// or for a date outside 1901 to 2099.
UtcTime ParseUtcTime(const std::string& text, const std::string& what);

struct SolarPosition {
  double azimuth_deg = 0.0;    ///< clockwise from true north, 0 to 360
  double elevation_deg = 0.0;  ///< above the horizon, refraction included
};

/// The sun seen from latitude (north positive) and longitude (east
/// positive) [deg] at `time`.
SolarPosition SunPosition(const UtcTime& time, double latitude_deg, double longitude_deg);

}  // namespace aar
