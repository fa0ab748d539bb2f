#include "aar/solar_position.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include "aar/error.h"

namespace aar {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

double Sin(double deg) { return std::sin(deg * kDeg); }
double Cos(double deg) { return std::cos(deg * kDeg); }
double Tan(double deg) { return std::tan(deg * kDeg); }
double Wrap360(double deg) { return deg - 360.0 * std::floor(deg / 360.0); }

bool LeapYear(int year) { return (year % 4 == 0 && year % 100 != 0) || year % 400 == 0; }

int DaysInMonth(int year, int month) {
  static const int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return month == 2 && LeapYear(year) ? 29 : kDays[month - 1];
}

// Julian day of a Gregorian date at `fraction` of the UTC day (Meeus, chapter 7).
double JulianDay(int year, int month, int day, double fraction) {
  if (month <= 2) {
    year -= 1;
    month += 12;
  }
  const int a = year / 100;
  const int b = 2 - a + a / 4;
  return std::floor(365.25 * (year + 4716)) + std::floor(30.6001 * (month + 1)) + day + b - 1524.5 + fraction;
}

// NOAA's fit of the standard atmosphere's refraction at an elevation [deg].
double RefractionDeg(double elevation_deg) {
  const double e = elevation_deg;
  double arcsec = 0.0;
  if (e > 85.0) {
    arcsec = 0.0;
  } else if (e > 5.0) {
    const double t = Tan(e);
    arcsec = 58.1 / t - 0.07 / (t * t * t) + 0.000086 / std::pow(t, 5);
  } else if (e > -0.575) {
    arcsec = 1735.0 + e * (-518.2 + e * (103.4 + e * (-12.79 + e * 0.711)));
  } else {
    arcsec = -20.772 / Tan(e);
  }
  return arcsec / 3600.0;
}

}  // namespace

UtcTime ParseUtcTime(const std::string& text, const std::string& what) {
  UtcTime t;
  int consumed = 0;
  const std::string bad = what + " '" + text + "': expected YYYY-MM-DDTHH:MM[:SS]Z in UTC";
  if (std::sscanf(text.c_str(), "%4d-%2d-%2dT%2d:%2d%n", &t.year, &t.month, &t.day, &t.hour, &t.minute, &consumed) !=
          5 ||
      consumed != 16) {
    throw Error(bad);
  }
  std::string rest = text.substr(static_cast<size_t>(consumed));
  if (!rest.empty() && rest[0] == ':') {
    char* end = nullptr;
    t.second = std::strtod(rest.c_str() + 1, &end);
    if (end == rest.c_str() + 1 || !(t.second >= 0.0 && t.second < 60.0)) throw Error(bad);
    rest = std::string(end);
  }
  if (rest != "Z") throw Error(bad);
  if (t.year < 1901 || t.year > 2099) throw Error(what + " '" + text + "': the solar position holds from 1901 to 2099");
  if (t.month < 1 || t.month > 12 || t.day < 1 || t.day > DaysInMonth(t.year, t.month) || t.hour > 23 ||
      t.minute > 59 || t.hour < 0 || t.minute < 0) {
    throw Error(what + " '" + text + "': not a date and time");
  }
  return t;
}

SolarPosition SunPosition(const UtcTime& time, double latitude_deg, double longitude_deg) {
  const double minutes = time.hour * 60.0 + time.minute + time.second / 60.0;  // of the UTC day
  const double jc = (JulianDay(time.year, time.month, time.day, minutes / 1440.0) - 2451545.0) / 36525.0;
  const double mean_longitude = Wrap360(280.46646 + jc * (36000.76983 + jc * 0.0003032));
  const double mean_anomaly = 357.52911 + jc * (35999.05029 - 0.0001537 * jc);
  const double eccentricity = 0.016708634 - jc * (0.000042037 + 0.0000001267 * jc);
  const double centre = Sin(mean_anomaly) * (1.914602 - jc * (0.004817 + 0.000014 * jc)) +
                        Sin(2.0 * mean_anomaly) * (0.019993 - 0.000101 * jc) + Sin(3.0 * mean_anomaly) * 0.000289;
  const double omega = 125.04 - 1934.136 * jc;  // longitude of the Moon's ascending node (nutation)
  const double apparent_longitude = mean_longitude + centre - 0.00569 - 0.00478 * Sin(omega);
  const double mean_obliquity = 23.0 + (26.0 + (21.448 - jc * (46.815 + jc * (0.00059 - jc * 0.001813))) / 60.0) / 60.0;
  const double obliquity = mean_obliquity + 0.00256 * Cos(omega);
  const double declination = std::asin(Sin(obliquity) * Sin(apparent_longitude)) / kDeg;
  const double y = Tan(obliquity / 2.0) * Tan(obliquity / 2.0);
  const double equation_of_time_min =
      4.0 / kDeg *
      (y * Sin(2.0 * mean_longitude) - 2.0 * eccentricity * Sin(mean_anomaly) +
       4.0 * eccentricity * y * Sin(mean_anomaly) * Cos(2.0 * mean_longitude) -
       0.5 * y * y * Sin(4.0 * mean_longitude) - 1.25 * eccentricity * eccentricity * Sin(2.0 * mean_anomaly));
  const double true_solar_min =
      std::fmod(std::fmod(minutes + equation_of_time_min + 4.0 * longitude_deg, 1440.0) + 1440.0, 1440.0);
  const double hour_angle = true_solar_min / 4.0 - 180.0;  // true solar time is in [0, 1440) minutes
  const double cos_zenith =
      Sin(latitude_deg) * Sin(declination) + Cos(latitude_deg) * Cos(declination) * Cos(hour_angle);
  const double zenith = std::acos(std::clamp(cos_zenith, -1.0, 1.0)) / kDeg;
  SolarPosition p;
  p.elevation_deg = 90.0 - zenith + RefractionDeg(90.0 - zenith);
  const double denominator = Cos(latitude_deg) * Sin(zenith);
  if (std::abs(denominator) < 1e-12) {
    p.azimuth_deg = latitude_deg > 0.0 ? 180.0 : 0.0;  // the sun at the zenith or the observer at a pole
  } else {
    const double a =
        std::acos(std::clamp((Sin(latitude_deg) * Cos(zenith) - Sin(declination)) / denominator, -1.0, 1.0)) / kDeg;
    p.azimuth_deg = hour_angle > 0.0 ? Wrap360(a + 180.0) : Wrap360(540.0 - a);
  }
  return p;
}

}  // namespace aar
