// aar-render: headless Vulkan stereo renderer for AAR research datasets.
// A table of subcommands, one RunFoo(argc, argv) each (argv[0] is
// "aar-render foo"): it parses its own flags, validates them and calls
// aar_renderer, where the work lives.

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "aar/error.h"
#include "aar/flight_path.h"
#include "aar/renderer/background.h"
#include "aar/renderer/dataset_writer.h"
#include "aar/renderer/msaa.h"
#include "aar/renderer/stereo_render_job.h"
#include "aar/renderer/vulkan_context.h"
#include "aar/solar_position.h"
#include "aar/text.h"

namespace {

constexpr const char* kDescription =
    "aar-render: renders the tanker's stereo cameras looking at a receiver aircraft, headless with Vulkan, "
    "into a self-describing dataset folder (docs/dataset-format.md).";

/// One subcommand: its name, the one-line description `aar-render --help` lists, and its entry point.
struct Command {
  const char* name;
  const char* description;
  int (*run)(int argc, char** argv);
};

int RunRender(int argc, char** argv);
int RunCalib(int argc, char** argv);
int RunFinalize(int argc, char** argv);
int RunDevices(int argc, char** argv);
int RunBench(int argc, char** argv);

const Command kCommands[] = {
    {"render", "render a flight path: one stereo pair and truth sidecar per sample", RunRender},
    {"calib", "render the calibration board at 12 poses into DATASET/calib/", RunCalib},
    {"finalize", "recompute manifest.json's file list (after sharded runs)", RunFinalize},
    {"devices", "list the Vulkan devices and their native MSAA counts", RunDevices},
    {"bench", "time stereo pairs per second per MSAA level (render, readback, encode, write), last pairs of the path",
     RunBench},
};

const Command& CommandNamed(const char* name) {
  for (const Command& command : kCommands) {
    if (std::strcmp(command.name, name) == 0) return command;
  }
  throw aar::Error(std::string("no subcommand ") + name);
}

/// The parser of one subcommand; a repeated flag: the last wins.
void ConfigureApp(CLI::App& app) { app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast); }

/// "30,45" for {30, 45}; "none" for no far boards.
std::string FarBoardsText(const std::vector<double>& distances_m) {
  std::string text;
  for (const double d : distances_m) {
    char buffer[32];
    const auto end = std::to_chars(buffer, buffer + sizeof(buffer), d).ptr;  // shortest round-trip form
    text += (text.empty() ? "" : ",") + std::string(buffer, end);
  }
  return text.empty() ? "none" : text;
}

/// Parses --far-boards: comma-separated distances [m], or "none".
std::vector<double> ParseFarBoards(const std::string& text) {
  std::vector<double> distances_m;
  if (text == "none") return distances_m;
  for (const std::string& field : aar::SplitCsvLine(text))
    distances_m.push_back(aar::ParseFiniteDouble(field, "--far-boards"));
  return distances_m;
}

/// Flags shared by render, calib and bench; the defaults are RenderJobOptions'.
struct JobFlags {
  aar::RenderJobOptions job;
  std::string frames;
  std::string shard;
  std::string background = aar::BackgroundName(aar::BackgroundOptions{}.kind);
  std::string far_boards = FarBoardsText(aar::RenderJobOptions{}.far_boards_m);
  std::optional<double> sun_azimuth_deg, sun_elevation_deg, latitude_deg, longitude_deg, heading_deg;
  std::string sun_time;
  bool daylight = false;
  std::optional<double> turbidity;
  bool night = false;
  std::optional<double> moonlight_lx;
  std::optional<double> floodlight_lx, floodlight_beam_deg;
  std::string shading = aar::ToString(aar::RenderJobOptions{}.shading);
};

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
  } else {
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
    cmd.add_option("--floodlight", f.floodlight_lx,
                   "the tanker's floodlight between the cameras, aimed at the path's nearest receiver position, "
                   "giving this illuminance there [lx], 0.1 to 10000 (e.g. 50 at night)");
    cmd.add_option("--floodlight-beam", f.floodlight_beam_deg,
                   "with --floodlight: the beam's spread, one standard deviation, 1 to 60 [deg] [default: 10]");
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

void Report(const aar::RenderJobResult& r, const std::filesystem::path& out) {
  const double pairs = static_cast<double>(r.rendered);
  std::fprintf(stderr, "%s: %zu pairs rendered, %zu already complete, device %s, MSAA %s\n", out.c_str(), r.rendered,
               r.skipped, r.device.c_str(), r.msaa_method.c_str());
  if (r.rendered > 0) {
    std::fprintf(stderr,
                 "per pair: render %.1f ms, readback %.1f ms; beside them encode %.1f ms, write %.1f ms; waiting for "
                 "the writer %.1f ms (%.2f pairs/s)\n",
                 r.times.render_ms / pairs, r.times.readback_ms / pairs, r.times.encode_ms / pairs,
                 r.times.write_ms / pairs, r.times.wait_ms / pairs, 1000.0 * pairs / r.times.wall_ms);
  }
  std::fprintf(stderr, "%s\n",
               r.complete ? "dataset complete: manifest.json lists every file with its SHA-256"
                          : "dataset incomplete: other frames are still missing (run the other "
                            "shards, then `aar-render finalize`)");
}

// render and calib: one dataset folder, the shared flags, one job.
int RunJob(int argc, char** argv, bool calib) {
  const Command& command = CommandNamed(calib ? "calib" : "render");
  CLI::App app{command.description};
  ConfigureApp(app);
  JobFlags flags;
  app.add_option("output", flags.job.output,
                 calib ? "dataset folder (created if needed)" : "dataset folder (created; re-running resumes)")
      ->required();
  AddJobFlags(app, flags, calib);
  CLI11_PARSE(app, argc, argv);
  flags.job.selection = aar::ParseFrameSelection(flags.frames, flags.shard);
  flags.job.background.kind = aar::ParseBackgroundKind(flags.background);
  if (!calib) flags.job.background.sun = ResolveSun(flags);
  if (!calib) flags.job.background.daylight = ResolveDaylight(flags);
  if (!calib) flags.job.background.night = ResolveNight(flags);
  if (!calib) flags.job.floodlight = ResolveFloodlight(flags);
  if (!calib) flags.job.shading = aar::ParseShading(flags.shading);
  if (calib) flags.job.far_boards_m = ParseFarBoards(flags.far_boards);
  const aar::RenderJobResult result =
      calib ? aar::RenderCalibrationJob(flags.job) : aar::RenderFlightPathJob(flags.job);
  Report(result, flags.job.output);
  return 0;
}

int RunRender(int argc, char** argv) { return RunJob(argc, argv, false); }

int RunCalib(int argc, char** argv) { return RunJob(argc, argv, true); }

int RunFinalize(int argc, char** argv) {
  CLI::App app{CommandNamed("finalize").description};
  ConfigureApp(app);
  std::filesystem::path dataset;
  app.add_option("dataset", dataset, "dataset folder")->required()->check(CLI::ExistingDirectory);
  CLI11_PARSE(app, argc, argv);
  const bool complete = aar::FinalizeManifest(dataset);
  std::fprintf(stderr, "%s: manifest %s\n", dataset.c_str(), complete ? "complete" : "incomplete (frames missing)");
  return complete ? 0 : 3;
}

int RunDevices(int argc, char** argv) {
  CLI::App app{CommandNamed("devices").description};
  ConfigureApp(app);
  CLI11_PARSE(app, argc, argv);
  for (const aar::DeviceInfo& d : aar::VulkanContext::ListDevices()) {
    std::ostringstream counts;
    for (int c : d.color_sample_counts) counts << (counts.tellp() > 0 ? "," : "") << c;
    std::printf("%s | %s | %s | Vulkan %s | MSAA native %s | standard sample locations %s\n", d.name.c_str(),
                d.driver_name.c_str(), d.driver_info.c_str(), d.api_version.c_str(), counts.str().c_str(),
                d.standard_sample_locations ? "yes" : "no");
  }
  return 0;
}

// Renders the last `pairs` samples once per level into a scratch folder and
// prints a Markdown table of per-pair stage times. Encode and write run on the
// writer thread beside the rendering; wall is the time per pair (pairs/s).
int RunBench(int argc, char** argv) {
  CLI::App app{CommandNamed("bench").description};
  ConfigureApp(app);
  JobFlags flags;
  std::vector<int> levels = {1, 4, 16};
  size_t pairs = 8;
  app.add_option("--levels", levels, "MSAA levels to time")->delimiter(',')->capture_default_str();
  app.add_option("--pairs", pairs, "pairs per level (the last ones of the flight path: receiver largest)")
      ->capture_default_str();
  AddJobFlags(app, flags, false);
  // Backgrounds to compare, each level timed with each in turn (noise drifts slowly).
  app.remove_option(app.get_option("--background"));
  std::vector<std::string> backgrounds = {"flat"};
  app.add_option("--backgrounds", backgrounds, "backgrounds to time side by side (flat, sky, terrain, clouds)")
      ->delimiter(',')
      ->capture_default_str();
  app.remove_option(app.get_option("--shading"));
  std::vector<std::string> shading_names = {"matte"};
  app.add_option("--shadings", shading_names,
                 "shadings to time side by side (matte, pbr; with +shadows, e.g. pbr+shadows, the sun's shadows too)")
      ->delimiter(',')
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  std::vector<aar::BackgroundKind> kinds;
  for (const std::string& name : backgrounds) kinds.push_back(aar::ParseBackgroundKind(name));
  struct Lighting {
    std::string name;
    aar::Shading shading;
    bool shadows;
  };
  std::vector<Lighting> shadings;
  for (const std::string& name : shading_names) {
    const std::string suffix = "+shadows";
    const bool shadows = name.size() > suffix.size() && name.ends_with(suffix);
    shadings.push_back({name, aar::ParseShading(shadows ? name.substr(0, name.size() - suffix.size()) : name),
                        shadows || flags.job.shadows});
  }
  flags.job.background.sun = ResolveSun(flags);
  flags.job.background.daylight = ResolveDaylight(flags);
  flags.job.background.night = ResolveNight(flags);
  flags.job.floodlight = ResolveFloodlight(flags);
  if (app.count("--msaa") > 0) {  // one level: the same as --levels with it alone
    if (app.count("--levels") > 0) throw aar::Error("--msaa and --levels: give one of them");
    levels = {flags.job.msaa};
  }
  for (int level : levels) aar::CheckMsaaLevel(level);  // all refused before the first is timed

  aar::RenderJobOptions job = flags.job;
  const size_t count = aar::ReadFlightPath(job.flight_path).size();
  job.selection.begin = count > pairs ? count - pairs : 0;
  job.progress = false;
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / ("aar-render-bench-" + std::to_string(::getpid()));
  std::printf(
      "| MSAA | background | shading | method | pairs | render ms | readback ms | encode ms | write ms | wait ms | "
      "wall ms | pairs/s |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int level : levels) {
    for (aar::BackgroundKind kind : kinds) {
      for (const Lighting& lighting : shadings) {
        job.msaa = level;
        job.background.kind = kind;
        job.shading = lighting.shading;
        job.shadows = lighting.shadows;
        job.output = root / ("x" + std::to_string(level) + "-" + aar::BackgroundName(kind) + "-" + lighting.name);
        std::filesystem::remove_all(job.output);
        const aar::RenderJobResult r = aar::RenderFlightPathJob(job);
        const double n = static_cast<double>(r.rendered);
        std::printf("| x%d | %s | %s | %s | %zu | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.2f |\n", level,
                    aar::BackgroundName(kind), lighting.name.c_str(), r.msaa_method.c_str(), r.rendered,
                    r.times.render_ms / n, r.times.readback_ms / n, r.times.encode_ms / n, r.times.write_ms / n,
                    r.times.wait_ms / n, r.times.wall_ms / n, 1000.0 * n / r.times.wall_ms);
        std::fflush(stdout);
      }
    }
  }
  std::filesystem::remove_all(root);
  return 0;
}

// No known subcommand: CLI11 prints the top-level help (`--help`) or the
// usual usage error (none given, or an unknown one).
int RunTopLevel(int argc, char** argv) {
  CLI::App app{kDescription};
  app.set_version_flag("--version", std::string("aar-render ") + AAR_VERSION + " (git " + AAR_GIT_HASH + ")");
  app.require_subcommand(1);
  for (const Command& command : kCommands) app.add_subcommand(command.name, command.description);
  CLI11_PARSE(app, argc, argv);
  return 0;
}

bool IsHelpFlag(const char* arg) { return std::strcmp(arg, "-h") == 0 || std::strcmp(arg, "--help") == 0; }

}  // namespace

int main(int argc, char** argv) {
  // `aar-render --help foo` is `aar-render foo --help`.
  if (argc == 3 && IsHelpFlag(argv[1])) std::swap(argv[1], argv[2]);
  try {
    for (const Command& command : kCommands) {
      if (argc < 2 || std::strcmp(argv[1], command.name) != 0) continue;
      // The subcommand sees "aar-render foo" as its program name, for its usage line.
      std::string program = std::string(argv[0]) + " " + command.name;
      argv[1] = program.data();
      return command.run(argc - 1, argv + 1);
    }
    return RunTopLevel(argc, argv);
  } catch (const aar::Error& e) {
    std::fprintf(stderr, "aar-render: error: %s\n", e.what());
    return 1;
  } catch (const std::filesystem::filesystem_error& e) {
    std::fprintf(stderr, "aar-render: error: %s\n", aar::FileSystemMessage(e).c_str());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aar-render: internal error: %s\n", e.what());
    return 2;
  }
}
