// aar-render: headless Vulkan stereo renderer for AAR research datasets.
// A table of subcommands, one RunFoo(argc, argv) each (argv[0] is
// "aar-render foo"): it parses its own flags, validates them and calls
// aar_renderer, where the work lives.

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstring>
#include <filesystem>
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
#include "job_flags.h"

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
  aar::JobFlags flags;
  app.add_option("output", flags.job.output,
                 calib ? "dataset folder (created if needed)" : "dataset folder (created; re-running resumes)")
      ->required();
  aar::AddJobFlags(app, flags, calib);
  CLI11_PARSE(app, argc, argv);
  flags.job.selection = aar::ParseFrameSelection(flags.frames, flags.shard);
  flags.job.background.kind = aar::ParseBackgroundKind(flags.background);
  if (calib) {
    aar::ResolveCalibFlags(flags);
  } else {
    aar::ResolveLightingFlags(flags);
    flags.job.shading = aar::ParseShading(flags.shading);
  }
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
  aar::JobFlags flags;
  std::vector<int> levels = {1, 4, 16};
  size_t pairs = 8;
  app.add_option("--levels", levels, "MSAA levels to time")->delimiter(',')->capture_default_str();
  app.add_option("--pairs", pairs, "pairs per level (the last ones of the flight path: receiver largest)")
      ->capture_default_str();
  aar::AddJobFlags(app, flags, false);
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
  aar::ResolveLightingFlags(flags);
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
