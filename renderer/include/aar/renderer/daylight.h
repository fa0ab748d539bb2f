#pragma once
// Daylight that follows the sun (docs/rendering.md, "Daylight"): the sun's
// colour and brightness after the atmosphere between it and a point, and the
// sky's radiance by direction from Preetham, Shirley and Smits's analytic
// model ("A Practical Analytic Model for Daylight", SIGGRAPH 1999), both in
// the renderer's linear units: 0.75 is the radiance of a white Lambertian
// surface facing the sun outside the atmosphere (scene.frag's kSunIntensity,
// the light every dataset without --daylight has). Pure maths, no GPU;
// shaders/background.frag and scene.frag evaluate the same model from the
// specialization constants the scene renderer sets from a Daylight.

#include <Eigen/Core>
#include <array>
#include <nlohmann/json.hpp>

namespace aar {

struct BackgroundOptions;

/// Channels' wavelengths [um] of the sun's transmittance: red, green, blue.
inline constexpr std::array<double, 3> kDaylightWavelengthsUm = {0.680, 0.550, 0.440};
/// background.frag's kPlainGround: the albedo of the untextured ground (--background sky).
inline constexpr std::array<double, 3> kPlainGroundAlbedo = {0.16, 0.17, 0.12};
/// Extraterrestrial solar illuminance [lx] (Darula, Kittler and Gueymard
/// 2005): the sky's luminance is scaled by 0.75 pi / this.
inline constexpr double kSolarIlluminanceLx = 133800.0;
/// The sun's mean angular radius [rad] (0.2666 deg).
inline constexpr double kSunAngularRadiusRad = 0.004653;
/// The moon's mean angular radius [rad] (0.2590 deg).
inline constexpr double kMoonAngularRadiusRad = 0.004520;
/// At night the shaders render radiance times this power of two, so that
/// moonlight stays in the normal range of the half-float render targets
/// (a white surface in 0.01 lx is 5.6e-8 in day units, below half's
/// smallest normal 6.1e-5); the camera's exposure (camera_exposure.h)
/// divides it out again.
inline constexpr double kNightRenderScale = 4096.0;

/// What the shaders' radiance is in day units: 1 by day, kNightRenderScale at night.
double RenderScale(const BackgroundOptions& options);
/// The light source's illuminance over the sun's, times RenderScale: 1 by
/// day; at night moonlight_lx / kSolarIlluminanceLx x kNightRenderScale.
double SourceScale(const BackgroundOptions& options);
/// The angular radius of the source's disc: the sun's, or the moon's at night [rad].
double SourceAngularRadiusRad(const BackgroundOptions& options);

/// Relative optical air mass at a zenith angle [deg] from 0 to 90 (Kasten and
/// Young 1989: 1 / (cos z + 0.50572 (96.07995 - z)^-1.6364)).
double RelativeAirMass(double zenith_deg);

/// Pressure at a height above sea level over that at sea level, the US
/// Standard Atmosphere 1976 (troposphere to 11 km, isothermal above).
double PressureRatio(double height_m);

/// Vertical optical depths at kDaylightWavelengthsUm of the atmosphere above
/// `height_m`: Rayleigh scattering (Leckner 1978, 0.008735 lambda^-4.08,
/// scaled by PressureRatio), aerosols (Angstrom, alpha 1.3, beta = 0.04608
/// turbidity - 0.04586 as in Preetham et al., falling with the haze's scale
/// height) and ozone's Chappuis band (absorption of Hillaire 2020 over a
/// 15 km column, all of it above the tanker).
Eigen::Vector3d VerticalOpticalDepth(double height_m, double turbidity, double haze_scale_height_m);

/// The direct sun's transmittance per channel to a point `height_m` up, with
/// the sun `elevation_deg` above the horizon: exp(-m tau).
Eigen::Vector3d SunTransmittance(double elevation_deg, double height_m, double turbidity, double haze_scale_height_m);

/// The sun's light at the tanker, per channel: 0.75 x SunTransmittance with
/// --daylight (x SourceScale: the moon's at night), else the fixed light's white 0.75.
Eigen::Vector3d SunLightAtTanker(const BackgroundOptions& options);

/// Preetham's sky for one turbidity and sun: the Perez distribution's
/// coefficients and zenith values of luminance Y and chromaticity x, y.
struct PreethamSky {
  std::array<std::array<double, 5>, 3> perez{};      ///< A..E of Y, x, y
  Eigen::Vector3d zenith = Eigen::Vector3d::Zero();  ///< Y [kcd/m^2], x, y at the zenith
  Eigen::Vector3d sun_in_level = Eigen::Vector3d::UnitZ();
  double sun_zenith_rad = 0.0;
  /// The source's illuminance over the sun's in render units (SourceScale):
  /// Radiance and ZenithOverPerez are scaled by it, Yxy is not.
  double scale = 1.0;

  /// Zenith luminance [kcd/m^2]: (4.0453 T - 4.9710) tan chi - 0.2155 T + 2.4192,
  /// chi = (4/9 - T/120) (pi - 2 theta_s).
  static double ZenithLuminance(double turbidity, double sun_zenith_rad);
  /// The zenith's Y (in the renderer's units), x and y, each over its Perez
  /// function at the zenith: times the Perez function of a direction, that
  /// direction's value (the background shader's kZenith).
  Eigen::Vector3d ZenithOverPerez() const;
  /// Y [kcd/m^2] for the sun, x, y of the sky in a level-frame direction;
  /// at and below the horizontal, the horizon's value in the direction's azimuth.
  Eigen::Vector3d Yxy(const Eigen::Vector3d& direction_in_level) const;
  /// The same in linear sRGB, the renderer's units (see the header comment).
  Eigen::Vector3d Radiance(const Eigen::Vector3d& direction_in_level) const;
};

/// Throws aar::Error for a turbidity outside 2 to 10, the model's range.
PreethamSky MakePreethamSky(double turbidity, const Eigen::Vector3d& sun_in_level);

/// CIE XYZ to linear sRGB (IEC 61966-2-1, D65).
Eigen::Vector3d LinearSrgbFromXyz(const Eigen::Vector3d& xyz);

/// Everything the shaders need, from the background options and the mean
/// albedo of what lies below (the ground or the cloud deck), linear RGB.
struct Daylight {
  PreethamSky sky;
  Eigen::Vector3d sun_at_tanker = Eigen::Vector3d::Zero();   ///< 0.75 x transmittance: scene.frag's sun light
  Eigen::Vector3d sun_at_surface = Eigen::Vector3d::Zero();  ///< the same at the ground or deck top
  /// Irradiance / pi of the sky on a level face looking up (the surface, or
  /// the aircraft: Preetham's sky is the ground's, the same at any height).
  Eigen::Vector3d sky_from_above = Eigen::Vector3d::Zero();
  /// What lights the surface: albedo x this is its radiance before haze
  /// (sun_at_surface x the sun's z + sky_from_above).
  Eigen::Vector3d surface_light = Eigen::Vector3d::Zero();
  /// Irradiance / pi at the tanker on a face looking down: the hazed surface
  /// and the horizon (BelowHorizonRadiance).
  Eigen::Vector3d sky_from_below = Eigen::Vector3d::Zero();
  /// The sun's disc radiance seen from the tanker: E / (pi r^2) in these units, sun_at_tanker / r^2.
  Eigen::Vector3d sun_disc = Eigen::Vector3d::Zero();
  double disc_radius_rad = kSunAngularRadiusRad;  ///< the source's angular radius (the moon's at night)
};

/// The daylight of options (daylight set, a background with a surface) over
/// a surface of mean albedo `surface_albedo`.
Daylight ComputeDaylight(const BackgroundOptions& options, const Eigen::Vector3d& surface_albedo);

/// The radiance of a level-frame direction below the horizontal as the
/// background shader gives it (the surface's lit albedo faded into the
/// horizon's radiance by the haze), or the horizon's radiance where the ray
/// misses the surface; `albedo` is the surface's there.
Eigen::Vector3d BelowHorizonRadiance(const BackgroundOptions& options, const Daylight& daylight,
                                     const Eigen::Vector3d& direction_in_level, const Eigen::Vector3d& albedo);

/// The manifest's frames.background.daylight: the model, its inputs and the
/// sun's transmittance at the tanker and at the surface; at night the moon's
/// illuminance and the render scale.
nlohmann::json DaylightJson(const BackgroundOptions& options);

}  // namespace aar
