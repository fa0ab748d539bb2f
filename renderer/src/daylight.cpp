#include "aar/renderer/daylight.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "aar/error.h"
#include "aar/renderer/background.h"
#include "aar/text.h"

namespace aar {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
/// 0.75 (a white surface facing the sun outside the atmosphere) per pi times
/// that sun's illuminance: the renderer's unit of radiance per cd/m^2.
constexpr double kUnitsPerCandela = 0.75 * kPi / kSolarIlluminanceLx;

double Perez(const std::array<double, 5>& c, double cos_theta, double gamma) {
  const double cos_gamma = std::cos(gamma);
  return (1.0 + c[0] * std::exp(c[1] / cos_theta)) *
         (1.0 + c[2] * std::exp(c[3] * gamma) + c[4] * cos_gamma * cos_gamma);
}

// The direct sun's transmittance to `height_m` for the options' sun and turbidity.
Eigen::Vector3d SunTransmittanceAt(const BackgroundOptions& options, double height_m) {
  const double elevation_deg = std::asin(std::clamp(SunInLevel(options).z(), -1.0, 1.0)) / kDeg;
  return SunTransmittance(elevation_deg, height_m, options.daylight->turbidity, options.haze_scale_height_m);
}

double SurfaceHeight(const BackgroundOptions& options) {
  return options.kind == BackgroundKind::kClouds ? options.cloud_top_m : 0.0;
}

// (1 / pi) x the integral of radiance(w) |w.z| over the upper (up) or lower
// hemisphere: irradiance / pi of a level face looking up or down. Midpoint
// rule, 64 elevations by 128 azimuths, in a fixed order.
template <typename Radiance>
Eigen::Vector3d HemisphereIrradiance(const Radiance& radiance, bool up) {
  constexpr int kElevations = 64, kAzimuths = 128;
  const double de = 0.5 * kPi / kElevations, da = 2.0 * kPi / kAzimuths;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int i = 0; i < kElevations; ++i) {
    const double e = (up ? 1.0 : -1.0) * (i + 0.5) * de;
    const double weight = std::abs(std::sin(e)) * std::cos(e) * de * da / kPi;
    for (int j = 0; j < kAzimuths; ++j) {
      const double a = (j + 0.5) * da;
      sum += weight * radiance(Eigen::Vector3d(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)));
    }
  }
  return sum;
}

}  // namespace

double RelativeAirMass(double zenith_deg) {
  const double z = std::clamp(zenith_deg, 0.0, 90.0);
  return 1.0 / (std::cos(z * kDeg) + 0.50572 * std::pow(96.07995 - z, -1.6364));
}

double PressureRatio(double height_m) {
  // US Standard Atmosphere 1976: lapse rate 6.5 K/km to 11 km, then isothermal at 216.65 K.
  constexpr double kTropopauseM = 11000.0;
  const double troposphere = [](double h) {
    return std::pow(1.0 - 2.25577e-5 * h, 5.25588);
  }(std::min(height_m, kTropopauseM));
  return height_m <= kTropopauseM ? troposphere : troposphere * std::exp(-(height_m - kTropopauseM) / 6341.6);
}

Eigen::Vector3d VerticalOpticalDepth(double height_m, double turbidity, double haze_scale_height_m) {
  const double beta = 0.04608 * turbidity - 0.04586;  // Angstrom's turbidity coefficient (Preetham et al.)
  const double aerosol_fraction = std::exp(-std::max(height_m, 0.0) / haze_scale_height_m);
  // Ozone's absorption [1/m] (Hillaire 2020) over a 15 km equivalent column.
  constexpr std::array<double, 3> kOzonePerM = {0.650e-6, 1.881e-6, 0.085e-6};
  Eigen::Vector3d tau;
  for (int c = 0; c < 3; ++c) {
    const double lambda = kDaylightWavelengthsUm[c];
    tau[c] = 0.008735 * std::pow(lambda, -4.08) * PressureRatio(height_m) +
             beta * std::pow(lambda, -1.3) * aerosol_fraction + kOzonePerM[c] * 15000.0;
  }
  return tau;
}

Eigen::Vector3d SunTransmittance(double elevation_deg, double height_m, double turbidity, double haze_scale_height_m) {
  const double m = RelativeAirMass(90.0 - elevation_deg);
  return (-m * VerticalOpticalDepth(height_m, turbidity, haze_scale_height_m)).array().exp().matrix();
}

double RenderScale(const BackgroundOptions& options) { return options.night ? kNightRenderScale : 1.0; }

double SourceScale(const BackgroundOptions& options) {
  return options.night ? options.night->moonlight_lx / kSolarIlluminanceLx * kNightRenderScale : 1.0;
}

double SourceAngularRadiusRad(const BackgroundOptions& options) {
  return options.night ? kMoonAngularRadiusRad : kSunAngularRadiusRad;
}

Eigen::Vector3d SunLightAtTanker(const BackgroundOptions& options) {
  if (!options.daylight) return Eigen::Vector3d::Constant(0.75);
  return 0.75 * SourceScale(options) * SunTransmittanceAt(options, options.altitude_m);
}

double PreethamSky::ZenithLuminance(double turbidity, double sun_zenith_rad) {
  const double chi = (4.0 / 9.0 - turbidity / 120.0) * (kPi - 2.0 * sun_zenith_rad);
  return (4.0453 * turbidity - 4.9710) * std::tan(chi) - 0.2155 * turbidity + 2.4192;
}

PreethamSky MakePreethamSky(double turbidity, const Eigen::Vector3d& sun_in_level) {
  if (!(turbidity >= 2.0 && turbidity <= 10.0)) {
    throw Error("--turbidity " + FormatFixed(turbidity, 3) +
                ": expected 2 (very clear) to 10 (hazy), Preetham's range");
  }
  const double t = turbidity;
  PreethamSky sky;
  sky.sun_in_level = sun_in_level.normalized();
  sky.sun_zenith_rad = std::acos(std::clamp(sky.sun_in_level.z(), -1.0, 1.0));
  sky.perez[0] = {0.1787 * t - 1.4630, -0.3554 * t + 0.4275, -0.0227 * t + 5.3251, 0.1206 * t - 2.5771,
                  -0.0670 * t + 0.3703};
  sky.perez[1] = {-0.0193 * t - 0.2592, -0.0665 * t + 0.0008, -0.0004 * t + 0.2125, -0.0641 * t - 0.8989,
                  -0.0033 * t + 0.0452};
  sky.perez[2] = {-0.0167 * t - 0.2608, -0.0950 * t + 0.0092, -0.0079 * t + 0.2102, -0.0441 * t - 1.6537,
                  -0.0109 * t + 0.0529};
  const double s = sky.sun_zenith_rad, s2 = s * s, s3 = s2 * s;
  const Eigen::Vector3d tv(t * t, t, 1.0);
  const Eigen::Vector3d x(0.00166 * s3 - 0.00375 * s2 + 0.00209 * s,
                          -0.02903 * s3 + 0.06377 * s2 - 0.03202 * s + 0.00394,
                          0.11693 * s3 - 0.21196 * s2 + 0.06052 * s + 0.25886);
  const Eigen::Vector3d y(0.00275 * s3 - 0.00610 * s2 + 0.00317 * s,
                          -0.04214 * s3 + 0.08970 * s2 - 0.04153 * s + 0.00516,
                          0.15346 * s3 - 0.26756 * s2 + 0.06670 * s + 0.26688);
  sky.zenith = Eigen::Vector3d(PreethamSky::ZenithLuminance(t, s), tv.dot(x), tv.dot(y));
  return sky;
}

Eigen::Vector3d PreethamSky::ZenithOverPerez() const {
  Eigen::Vector3d out;
  for (int k = 0; k < 3; ++k) out[k] = zenith[k] / Perez(perez[k], 1.0, sun_zenith_rad);
  out[0] *= 1000.0 * kUnitsPerCandela * scale;
  return out;
}

Eigen::Vector3d PreethamSky::Yxy(const Eigen::Vector3d& direction_in_level) const {
  Eigen::Vector3d d = direction_in_level.normalized();
  if (d.z() < 1e-3) {
    // At and below the horizontal: the horizon in this azimuth (the Perez
    // gradation term is 1 there; cos theta 1e-3 makes exp(B / cos) vanish).
    const Eigen::Vector2d horizontal =
        d.head<2>().squaredNorm() > 1e-12 ? Eigen::Vector2d(d.head<2>().normalized()) : Eigen::Vector2d(1.0, 0.0);
    d = Eigen::Vector3d(horizontal.x(), horizontal.y(), 1e-3);
  }
  const double cos_theta = d.z();
  const double gamma = std::acos(std::clamp(d.normalized().dot(sun_in_level), -1.0, 1.0));
  Eigen::Vector3d out;
  for (int k = 0; k < 3; ++k) {
    out[k] = zenith[k] * Perez(perez[k], cos_theta, gamma) / Perez(perez[k], 1.0, sun_zenith_rad);
  }
  return out;
}

Eigen::Vector3d LinearSrgbFromXyz(const Eigen::Vector3d& xyz) {
  Eigen::Matrix3d m;
  m << 3.2404542, -1.5371385, -0.4985314, -0.9692660, 1.8760108, 0.0415560, 0.0556434, -0.2040259, 1.0572252;
  return m * xyz;
}

Eigen::Vector3d PreethamSky::Radiance(const Eigen::Vector3d& direction_in_level) const {
  const Eigen::Vector3d v = Yxy(direction_in_level);
  const double luminance = std::max(v[0], 0.0) * 1000.0 * kUnitsPerCandela * scale;
  const Eigen::Vector3d xyz(v[1] / v[2] * luminance, luminance, (1.0 - v[1] - v[2]) / v[2] * luminance);
  return LinearSrgbFromXyz(xyz).cwiseMax(0.0);
}

Eigen::Vector3d BelowHorizonRadiance(const BackgroundOptions& options, const Daylight& daylight,
                                     const Eigen::Vector3d& direction_in_level, const Eigen::Vector3d& albedo) {
  const Eigen::Vector3d airlight = daylight.sky.Radiance(direction_in_level);
  const double surface_m = SurfaceHeight(options);
  const std::optional<double> t =
      SphereHitParameter(direction_in_level, options.altitude_m - surface_m, kEarthRadiusM + surface_m);
  if (!t) return airlight;
  const double length_m = *t * direction_in_level.norm();
  const double transmittance = std::exp(-HazeOpticalDepth(length_m, options.altitude_m, surface_m, options));
  return (1.0 - transmittance) * airlight + transmittance * albedo.cwiseProduct(daylight.surface_light);
}

Daylight ComputeDaylight(const BackgroundOptions& options, const Eigen::Vector3d& surface_albedo) {
  if (!options.daylight) throw Error("ComputeDaylight: the options have no daylight");
  const Eigen::Vector3d sun = SunInLevel(options);
  Daylight d;
  d.sky = MakePreethamSky(options.daylight->turbidity, sun);
  d.sky.scale = SourceScale(options);
  d.sun_at_tanker = SunLightAtTanker(options);
  d.sun_at_surface = 0.75 * SourceScale(options) * SunTransmittanceAt(options, SurfaceHeight(options));
  d.sky_from_above = HemisphereIrradiance([&](const Eigen::Vector3d& w) { return d.sky.Radiance(w); }, true);
  d.surface_light = d.sun_at_surface * std::max(sun.z(), 0.0) + d.sky_from_above;
  d.sky_from_below = HemisphereIrradiance(
      [&](const Eigen::Vector3d& w) { return BelowHorizonRadiance(options, d, w, surface_albedo); }, false);
  d.disc_radius_rad = SourceAngularRadiusRad(options);
  d.sun_disc = d.sun_at_tanker / (d.disc_radius_rad * d.disc_radius_rad);
  return d;
}

nlohmann::json DaylightJson(const BackgroundOptions& options) {
  const double turbidity = options.daylight->turbidity;
  const Eigen::Vector3d at_tanker = SunTransmittanceAt(options, options.altitude_m);
  const Eigen::Vector3d at_surface = SunTransmittanceAt(options, SurfaceHeight(options));
  const PreethamSky sky = MakePreethamSky(turbidity, SunInLevel(options));
  nlohmann::json j = {
      {"model",
       "sky: Preetham, Shirley and Smits 1999; sun: Kasten-Young air mass, Rayleigh (Leckner), Angstrom "
       "aerosols, ozone (docs/rendering.md, \"Daylight\")"},
      {"turbidity", turbidity},
      {"wavelengths_um", kDaylightWavelengthsUm},
      {"sun_transmittance_at_tanker", {at_tanker.x(), at_tanker.y(), at_tanker.z()}},
      {"sun_transmittance_at_surface", {at_surface.x(), at_surface.y(), at_surface.z()}},
      {"zenith_luminance_kcd_m2", sky.zenith.x()},
      {"zenith_chromaticity_xy", {sky.zenith.y(), sky.zenith.z()}},
      {"sun_disc", "rendered where in view, angular radius " + FormatFixed(kSunAngularRadiusRad, 6) + " rad"}};
  if (options.night) {
    j["night"] = {
        {"moonlight_lx", options.night->moonlight_lx},
        {"source",
         "the moon at frames.sun's direction: the daylight model for a sun of the moon's illuminance "
         "(Jensen et al. 2001), its disc of angular radius " +
             FormatFixed(kMoonAngularRadiusRad, 6) + " rad"},
        {"render_scale", kNightRenderScale},
        {"zenith_luminance_cd_m2", sky.zenith.x() * 1000.0 * options.night->moonlight_lx / kSolarIlluminanceLx}};
  }
  return j;
}

}  // namespace aar
