#include "job_flags.h"

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>

#include "aar/error.h"
#include "aar/solar_position.h"
#include "aar/text.h"

namespace aar {

std::string FarBoardsText(const std::vector<double>& distances_m) {
  std::string text;
  for (const double d : distances_m) {
    char buffer[32];
    const auto end = std::to_chars(buffer, buffer + sizeof(buffer), d).ptr;  // shortest round-trip form
    text += (text.empty() ? "" : ",") + std::string(buffer, end);
  }
  return text.empty() ? "none" : text;
}

std::vector<double> ParseFarBoards(const std::string& text) {
  std::vector<double> distances_m;
  if (text == "none") return distances_m;
  for (const std::string& field : aar::SplitCsvLine(text))
    distances_m.push_back(aar::ParseFiniteDouble(field, "--far-boards"));
  return distances_m;
}

namespace {

// The sun the flags give: an azimuth and elevation, or a time and place;
// none of them leaves the default sun.
std::optional<aar::SunOptions> ResolveSun(const JobFlags& f) {
  const bool direct = f.sun_azimuth_deg || f.sun_elevation_deg;
  const bool dated = !f.sun_time.empty() || f.latitude_deg || f.longitude_deg || f.heading_deg;
  if (!direct && !dated) return std::nullopt;
  if (direct && dated) {
    throw aar::Error("--sun-azimuth/--sun-elevation or --sun-time/--latitude/--longitude/--heading: give one way");
  }
  aar::SunOptions sun;
  if (direct) {
    if (!f.sun_azimuth_deg || !f.sun_elevation_deg) throw aar::Error("--sun-azimuth and --sun-elevation: give both");
    sun.azimuth_deg = *f.sun_azimuth_deg;
    sun.elevation_deg = *f.sun_elevation_deg;
    sun.source = "--sun-azimuth " + aar::FormatFixed(sun.azimuth_deg, 3) + " --sun-elevation " +
                 aar::FormatFixed(sun.elevation_deg, 3);
    return sun;
  }
  if (f.sun_time.empty() || !f.latitude_deg || !f.longitude_deg || !f.heading_deg) {
    throw aar::Error("--sun-time, --latitude, --longitude and --heading: give all four");
  }
  if (!(std::abs(*f.latitude_deg) <= 90.0)) throw aar::Error("--latitude: expected -90 to 90 deg");
  if (!(std::abs(*f.longitude_deg) <= 180.0)) throw aar::Error("--longitude: expected -180 to 180 deg");
  if (!(*f.heading_deg >= 0.0 && *f.heading_deg < 360.0)) throw aar::Error("--heading: expected 0 to 360 deg");
  const aar::SolarPosition p =
      aar::SunPosition(aar::ParseUtcTime(f.sun_time, "--sun-time"), *f.latitude_deg, *f.longitude_deg);
  if (p.elevation_deg < 0.0) {
    throw aar::Error("--sun-time " + f.sun_time + ": the sun is " + aar::FormatFixed(-p.elevation_deg, 1) +
                     " deg below the horizon there (night has no sun yet)");
  }
  sun.azimuth_deg = p.azimuth_deg - *f.heading_deg;
  sun.elevation_deg = p.elevation_deg;
  sun.source = "NOAA solar position at " + f.sun_time + ", latitude " + aar::FormatFixed(*f.latitude_deg, 6) +
               ", longitude " + aar::FormatFixed(*f.longitude_deg, 6) + ", heading " +
               aar::FormatFixed(*f.heading_deg, 3) + " deg true: azimuth " + aar::FormatFixed(p.azimuth_deg, 3) +
               " deg true";
  return sun;
}

// --daylight and its --turbidity (--night's sky is daylight's, scaled).
std::optional<aar::DaylightOptions> ResolveDaylight(const JobFlags& f) {
  if (f.daylight && f.night) throw aar::Error("--daylight and --night: give one of them");
  if (!f.daylight && !f.night) {
    if (f.turbidity) throw aar::Error("--turbidity: only with --daylight or --night");
    return std::nullopt;
  }
  aar::DaylightOptions daylight;
  if (f.turbidity) daylight.turbidity = *f.turbidity;
  return daylight;
}

// --night and its --moonlight; the moon takes the sun's direction, which a
// date and time cannot give (they give the sun's).
std::optional<aar::NightOptions> ResolveNight(const JobFlags& f) {
  if (!f.night) {
    if (f.moonlight_lx) throw aar::Error("--moonlight: only with --night");
    return std::nullopt;
  }
  if (!f.sun_time.empty()) {
    throw aar::Error(
        "--night and --sun-time: the time gives the sun's place; give the moon's with --sun-azimuth "
        "and --sun-elevation");
  }
  aar::NightOptions night;
  if (f.moonlight_lx) night.moonlight_lx = *f.moonlight_lx;
  return night;
}

// --floodlight and its --floodlight-beam.
std::optional<aar::FloodlightOptions> ResolveFloodlight(const JobFlags& f) {
  if (!f.floodlight_lx) {
    if (f.floodlight_beam_deg) throw aar::Error("--floodlight-beam: only with --floodlight");
    return std::nullopt;
  }
  aar::FloodlightOptions flood;
  flood.illuminance_lx = *f.floodlight_lx;
  if (f.floodlight_beam_deg) flood.beam_sigma_deg = *f.floodlight_beam_deg;
  return flood;
}

// --auto-exposure and its --ae-target, --ae-time-constant.
std::optional<AutoExposureOptions> ResolveAutoExposure(const JobFlags& f) {
  if (!f.auto_exposure) {
    if (f.ae_target || f.ae_time_constant_s || f.ae_max_ev) {
      throw Error("--ae-target, --ae-time-constant and --ae-max-ev: only with --auto-exposure");
    }
    return std::nullopt;
  }
  AutoExposureOptions ae;
  if (f.ae_target) ae.target = *f.ae_target;
  if (f.ae_time_constant_s) ae.time_constant_s = *f.ae_time_constant_s;
  if (f.ae_max_ev) ae.max_ev = *f.ae_max_ev;
  ae.Check();
  return ae;
}

// --airspeed, --sky-temperature, --nacelle-excess: a thermal rig's scene, where any is given.
std::optional<ThermalSceneOptions> ResolveThermal(const JobFlags& f) {
  if (!f.airspeed_mps && !f.sky_temperature_k && !f.nacelle_excess_k && !f.board_temperature_k) return std::nullopt;
  ThermalSceneOptions thermal;
  if (f.airspeed_mps) thermal.airspeed_mps = *f.airspeed_mps;
  if (f.sky_temperature_k) thermal.sky_temperature_k = *f.sky_temperature_k;
  if (f.nacelle_excess_k) thermal.nacelle_excess_k = *f.nacelle_excess_k;
  if (f.board_temperature_k) thermal.board_temperature_k = *f.board_temperature_k;
  thermal.Check();
  return thermal;
}

// The background flags of `render` (and `bench`); the defaults are BackgroundOptions'.
void AddBackgroundFlags(CLI::App& cmd, JobFlags& f, bool kind) {
  aar::BackgroundOptions& b = f.job.background;
  if (kind) {
    cmd.add_option("--background", f.background,
                   "behind the receiver: flat (uniform sky, the thesis's), sky (horizon, sky gradient, plain hazy "
                   "ground), terrain (procedural fields, roads, water), clouds (an overcast deck)")
        ->capture_default_str();
  }
  cmd.add_option("--altitude", b.altitude_m, "tanker altitude above the ground [m] (sky, terrain, clouds)")
      ->capture_default_str();
  cmd.add_option("--cloud-top", b.cloud_top_m, "cloud deck top above the ground [m] (clouds)")->capture_default_str();
  cmd.add_option("--tanker-roll", b.tanker_roll_deg, "tanker roll [deg], frames.md conventions (moves the horizon)")
      ->capture_default_str();
  cmd.add_option("--tanker-pitch", b.tanker_pitch_deg, "tanker pitch [deg], positive nose down (moves the horizon)")
      ->capture_default_str();
  cmd.add_option("--visibility", b.visibility_m, "sea-level visibility of the haze [m] (2 % contrast)")
      ->capture_default_str();
  cmd.add_option("--background-seed", b.seed, "seed of the terrain and cloud textures")->capture_default_str();
  cmd.add_option("--sun-azimuth", f.sun_azimuth_deg,
                 "the sun's azimuth, clockwise from the tanker's heading seen from above [deg] (with "
                 "--sun-elevation; default: 52 deg left of the heading, 55 deg up)");
  cmd.add_option("--sun-elevation", f.sun_elevation_deg, "the sun's elevation above the horizon, 0 to 90 [deg]");
  cmd.add_option("--sun-time", f.sun_time,
                 "the sun where it is at this UTC time, YYYY-MM-DDTHH:MM[:SS]Z (NOAA's solar position; with "
                 "--latitude, --longitude, --heading)");
  cmd.add_option("--latitude", f.latitude_deg, "with --sun-time: the tanker's latitude, north positive [deg]");
  cmd.add_option("--longitude", f.longitude_deg, "with --sun-time: the tanker's longitude, east positive [deg]");
  cmd.add_option("--heading", f.heading_deg, "with --sun-time: the tanker's true heading, 0 to 360 [deg]");
  cmd.add_flag("--daylight", f.daylight,
               "the sun's colour and brightness after the atmosphere, Preetham's sky for the sun, the aircraft lit "
               "by that sky and by the ground or clouds below, the sun's disc in view (sky, terrain, clouds)");
  cmd.add_option("--turbidity", f.turbidity,
                 "with --daylight or --night: the atmosphere's turbidity, 2 (very clear) to 10 (hazy) [default: 3]");
  cmd.add_flag("--night", f.night,
               "night: the moon at --sun-azimuth/--sun-elevation (default: the default sun's place), its light and "
               "the sky it scatters (the daylight model scaled to the moon); set --exposure-ev, a camera's exposure "
               "at night (sky, terrain, clouds)");
  cmd.add_option("--moonlight", f.moonlight_lx,
                 "with --night: the moon's illuminance outside the atmosphere, 0 (no moon) to 1 lx [default: 0.25, "
                 "a full moon]");
}

// A flight-path job's path, models and what moves during the exposure.
void AddSceneFlags(CLI::App& cmd, JobFlags& f) {
  cmd.add_option("--flight-path", f.job.flight_path,
                 "flight-path CSV (time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg, optionally "
                 "boom_pitch_deg,boom_roll_deg,boom_extension_m: then the boom is in the scene)")
      ->capture_default_str();
  cmd.add_option("--receiver", f.job.receiver_model, "receiver glTF")->capture_default_str();
  cmd.add_option("--tanker", f.job.tanker_model, "tanker glTF")->capture_default_str();
  cmd.add_flag("--boom", f.job.boom,
               "put the boom in the scene for a flight path without boom columns (stowed: out of view)");
  cmd.add_option("--boom-model", f.job.boom_model, "boom glTF, fixed part")->capture_default_str();
  cmd.add_option("--boom-tube-model", f.job.boom_tube_model, "boom glTF, telescoping tube")->capture_default_str();
  cmd.add_option("--propellers", f.job.propeller_rpm,
                 "engine speed [rpm] of the receiver's two four-blade propellers (0: none, as in the thesis; "
                 "e.g. 1700); blurred with --shutter-ms")
      ->capture_default_str();
  cmd.add_option("--propeller-model", f.job.propeller_model, "propeller glTF")->capture_default_str();
  cmd.add_flag("--receiver-lights", f.job.receiver_lights,
               "the receiver's position lights (red left, green right, white tail), red anti-collision beacons "
               "and white strobes, flashing once a second (14 CFR 23.1391-23.1401 intensities)");
  cmd.add_option("--shutter-ms", f.job.shutter_ms,
                 "exposure time [ms] centred on each sample: the receiver and its propellers move during it "
                 "(motion blur); 0: an instant")
      ->capture_default_str();
  cmd.add_option("--time-samples", f.job.time_samples,
                 "instants the exposure is rendered at, a power of two (with --shutter-ms; cost: max(this, MSAA "
                 "passes) passes per view)")
      ->capture_default_str();
  cmd.add_option("--readout-bands", f.job.readout_bands,
                 "bands of rows a rolling shutter's frame is rendered in, each at its own instant (a rig whose "
                 "sensor.readout_ms > 0; a row's instant is off by at most readout / (2 bands)), 1 to 1024")
      ->capture_default_str();
}

// A flight-path job's light: shading, shadows, the camera's exposure, the floodlight.
void AddLightFlags(CLI::App& cmd, JobFlags& f) {
  cmd.add_option("--shading", f.shading,
                 "how the aircraft are lit: matte (Lambertian, the default) or pbr (the models' glTF "
                 "metallic-roughness materials, with the sun's and the sky's specular reflection)")
      ->capture_default_str();
  cmd.add_flag("--shadows", f.job.shadows,
               "the sun's shadows on the receiver: what the tanker, the boom, the receiver and its propellers "
               "cast on it (a shadow map per instant; docs/rendering.md, \"Shadows\")");
  cmd.add_option("--exposure-ev", f.job.exposure_ev,
                 "the camera's exposure over the rig's [EV, powers of two], -10 to 24: more light on the sensor "
                 "(a longer shutter, a wider aperture); at night about 10 to 14 with --floodlight")
      ->capture_default_str();
  cmd.add_flag("--auto-exposure", f.auto_exposure,
               "the camera meters each frame and sets the next one's exposure towards --ae-target through a lag "
               "(--ae-time-constant), from --exposure-ev at frame 0 (both cameras alike; docs/rendering.md, "
               "\"Exposure and night\")");
  cmd.add_option("--ae-target", f.ae_target,
                 "with --auto-exposure: the mean luminance aimed at, of the image's full scale [default: 0.18, "
                 "middle grey]");
  cmd.add_option("--ae-time-constant", f.ae_time_constant_s,
                 "with --auto-exposure: the lag's time constant [s], 0 (the next frame meets the target) to 60 "
                 "[default: 0.1]");
  cmd.add_option("--ae-max-ev", f.ae_max_ev,
                 "with --auto-exposure: the camera's most exposure over the rig's [EV] (longest shutter, widest "
                 "aperture, highest gain), -10 to 24 [default: 24]");
  cmd.add_option("--airspeed", f.airspeed_mps,
                 "a thermal rig (lwir): the aircraft's true airspeed, their skins at its recovery temperature "
                 "[m/s] [default: 120]");
  cmd.add_option("--sky-temperature", f.sky_temperature_k,
                 "a thermal rig: the flat sky's brightness temperature in the band [K] [default: 220]");
  cmd.add_option("--nacelle-excess", f.nacelle_excess_k,
                 "a thermal rig: the receiver's engine nacelles this much warmer than its skin [K] [default: 40]");
  cmd.add_option("--floodlight", f.floodlight_lx,
                 "the tanker's floodlight between the cameras, aimed at the path's nearest receiver position, "
                 "giving this illuminance there [lx], 0.1 to 10000 (e.g. 50 at night)");
  cmd.add_option("--floodlight-beam", f.floodlight_beam_deg,
                 "with --floodlight: the beam's spread, one standard deviation, 1 to 60 [deg] [default: 10]");
}

}  // namespace

void AddJobFlags(CLI::App& cmd, JobFlags& f, bool calib) {
  cmd.add_option("--rig", f.job.rig, "camera rig JSON")->capture_default_str();
  if (calib) {
    cmd.add_option("--board", f.job.board_model, "calibration board glTF")->capture_default_str();
    cmd.add_option("--far-boards", f.far_boards,
                   "also render the twelve board tilts at these distances along the optical axis [m] (36 pairs by "
                   "default; one distance alone leaves focal length and baseline confounded); none: the thesis's "
                   "twelve near boards only")
        ->capture_default_str();
    cmd.add_flag("--corner-boards", f.job.corner_boards,
                 "also render 8 boards pushed towards the image corners and edges (covers the periphery, where lens "
                 "distortion is largest)");
    cmd.add_option("--board-temperature", f.board_temperature_k,
                   "a thermal rig (lwir): the heated board's temperature, its light squares high-emissivity paint and "
                   "its dark ones polished metal [K] [default: 320]");
  } else {
    AddSceneFlags(cmd, f);
    AddLightFlags(cmd, f);
    cmd.add_flag("--depth", f.job.depth,
                 "also write left-camera ground-truth depth (EXR, metres), object ids and receiver silhouette");
    cmd.add_flag("--depth-right", f.job.depth_right, "also write the same for the right camera (implies --depth)");
    AddBackgroundFlags(cmd, f, true);
  }
  cmd.add_option("--msaa", f.job.msaa, "samples per pixel: 1, 4, 8, 16 or 32 (composed when not native)")
      ->capture_default_str();
  cmd.add_option("--anisotropy", f.job.anisotropy, "texture anisotropic filtering, 1 (trilinear) to 16")
      ->capture_default_str();
  cmd.add_option("--frames", f.frames, "half-open range a:b of frame indices (e.g. 0:100, 250:)");
  cmd.add_option("--shard", f.shard,
                 "render frames i with i % N == K (K/N); defaults to SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT");
  cmd.add_option("--device", f.job.device, "Vulkan device name substring (default: lavapipe, else the first)");
  cmd.add_flag(
      "--no-progress", [&f](int64_t) { f.job.progress = false; }, "no progress line on stderr");
}

void ResolveLightingFlags(JobFlags& f) {
  f.job.background.sun = ResolveSun(f);
  f.job.background.daylight = ResolveDaylight(f);
  f.job.background.night = ResolveNight(f);
  f.job.floodlight = ResolveFloodlight(f);
  f.job.auto_exposure = ResolveAutoExposure(f);
  f.job.thermal = ResolveThermal(f);
}

void ResolveCalibFlags(JobFlags& f) {
  f.job.far_boards_m = ParseFarBoards(f.far_boards);
  f.job.thermal = ResolveThermal(f);
}

}  // namespace aar
