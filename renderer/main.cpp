// aar-render: headless Vulkan stereo renderer for AAR research datasets.
// A thin table of subcommands; the work lives in aar_renderer.

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <sstream>

#include <unistd.h>

#include <CLI/CLI.hpp>

#include "aar/error.h"
#include "aar/flight_path.h"
#include "aar/renderer/dataset_writer.h"
#include "aar/renderer/stereo_render_job.h"
#include "aar/renderer/vulkan_context.h"

namespace {

struct CommonFlags {
  aar::RenderJobOptions job;
  std::string frames;
  std::string shard;
};

void AddCommonFlags(CLI::App* cmd, CommonFlags& f, bool calib) {
  cmd->add_option("--rig", f.job.rig, "camera rig JSON")->capture_default_str();
  if (calib) {
    cmd->add_option("--board", f.job.board_model, "calibration board glTF")->capture_default_str();
  } else {
    cmd->add_option("--flight-path", f.job.flight_path, "flight-path CSV (time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg)")
        ->capture_default_str();
    cmd->add_option("--receiver", f.job.receiver_model, "receiver glTF")->capture_default_str();
    cmd->add_option("--tanker", f.job.tanker_model, "tanker glTF")->capture_default_str();
    cmd->add_flag("--depth", f.job.depth, "also write left-camera ground-truth depth (EXR, metres)");
  }
  cmd->add_option("--msaa", f.job.msaa, "samples per pixel: 1, 4, 8, 16 or 32 (composed when not native)")
      ->capture_default_str();
  cmd->add_option("--anisotropy", f.job.anisotropy, "texture anisotropic filtering, 1 (trilinear) to 16")
      ->capture_default_str();
  cmd->add_option("--frames", f.frames, "half-open range a:b of frame indices (e.g. 0:100, 250:)");
  cmd->add_option("--shard", f.shard,
                  "render frames i with i % N == K (K/N); defaults to SLURM_ARRAY_TASK_ID/SLURM_ARRAY_TASK_COUNT");
  cmd->add_option("--device", f.job.device, "Vulkan device name substring (default: lavapipe, else the first)");
  cmd->add_flag("--no-progress", [&f](int64_t) { f.job.progress = false; }, "no progress line on stderr");
}

void Report(const aar::RenderJobResult& r, const std::filesystem::path& out) {
  const double pairs = static_cast<double>(r.rendered);
  const double total = r.times.render_ms + r.times.readback_ms + r.times.encode_ms + r.times.write_ms;
  std::fprintf(stderr, "%s: %zu pairs rendered, %zu already complete, device %s, MSAA %s\n", out.c_str(), r.rendered,
               r.skipped, r.device.c_str(), r.msaa_method.c_str());
  if (r.rendered > 0) {
    std::fprintf(stderr, "per pair: render %.1f ms, readback %.1f ms, encode %.1f ms, write %.1f ms (%.2f pairs/s)\n",
                 r.times.render_ms / pairs, r.times.readback_ms / pairs, r.times.encode_ms / pairs,
                 r.times.write_ms / pairs, 1000.0 * pairs / total);
  }
  std::fprintf(stderr, "%s\n", r.complete ? "dataset complete: manifest.json lists every file with its SHA-256"
                                          : "dataset incomplete: other frames are still missing (run the other "
                                            "shards, then `aar-render finalize`)");
}

// Renders the last `pairs` samples once per level into a scratch folder and
// prints a Markdown table of per-pair stage times.
void RunBench(aar::RenderJobOptions job, const std::vector<int>& levels, size_t pairs) {
  const size_t count = aar::ReadFlightPath(job.flight_path).size();
  job.selection.begin = count > pairs ? count - pairs : 0;
  job.progress = false;
  const std::filesystem::path root = job.output;
  std::printf("| MSAA | method | pairs | render ms | readback ms | encode ms | write ms | pairs/s |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  for (int level : levels) {
    job.msaa = level;
    job.output = root / ("x" + std::to_string(level));
    std::filesystem::remove_all(job.output);
    const aar::RenderJobResult r = aar::RenderFlightPathJob(job);
    const double n = static_cast<double>(r.rendered);
    const double total = r.times.render_ms + r.times.readback_ms + r.times.encode_ms + r.times.write_ms;
    std::printf("| x%d | %s | %zu | %.1f | %.1f | %.1f | %.1f | %.2f |\n", level, r.msaa_method.c_str(), r.rendered,
                r.times.render_ms / n, r.times.readback_ms / n, r.times.encode_ms / n, r.times.write_ms / n,
                1000.0 * n / total);
    std::fflush(stdout);
  }
  std::filesystem::remove_all(root);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "aar-render: renders the tanker's stereo cameras looking at a receiver aircraft, headless with Vulkan, "
      "into a self-describing dataset folder (docs/dataset-format.md)."};
  app.require_subcommand(1);
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);  // a repeated flag: the last wins

  CommonFlags render_flags;
  CLI::App* render = app.add_subcommand("render", "render a flight path: one stereo pair and truth sidecar per sample");
  render->add_option("output", render_flags.job.output, "dataset folder (created; re-running resumes)")->required();
  AddCommonFlags(render, render_flags, false);

  CommonFlags calib_flags;
  CLI::App* calib = app.add_subcommand("calib", "render the calibration board at 12 poses into DATASET/calib/");
  calib->add_option("output", calib_flags.job.output, "dataset folder (created if needed)")->required();
  AddCommonFlags(calib, calib_flags, true);

  std::filesystem::path finalize_dir;
  CLI::App* finalize = app.add_subcommand("finalize", "recompute manifest.json's file list (after sharded runs)");
  finalize->add_option("dataset", finalize_dir, "dataset folder")->required()->check(CLI::ExistingDirectory);

  CLI::App* devices = app.add_subcommand("devices", "list the Vulkan devices and their native MSAA counts");

  CommonFlags bench_flags;
  std::vector<int> bench_levels = {1, 4, 16};
  size_t bench_pairs = 8;
  CLI::App* bench = app.add_subcommand(
      "bench", "time stereo pairs per second per MSAA level (render, readback, encode, write), last pairs of the path");
  bench->add_option("--levels", bench_levels, "MSAA levels to time")->delimiter(',')->capture_default_str();
  bench->add_option("--pairs", bench_pairs, "pairs per level (the last ones of the flight path: receiver largest)")
      ->capture_default_str();
  AddCommonFlags(bench, bench_flags, false);
  bench_flags.job.output = std::filesystem::temp_directory_path() / ("aar-render-bench-" + std::to_string(::getpid()));

  CLI11_PARSE(app, argc, argv);
  try {
    if (render->parsed() || calib->parsed()) {
      CommonFlags& f = render->parsed() ? render_flags : calib_flags;
      f.job.selection = aar::ParseFrameSelection(f.frames, f.shard);
      const aar::RenderJobResult result =
          render->parsed() ? aar::RenderFlightPathJob(f.job) : aar::RenderCalibrationJob(f.job);
      Report(result, f.job.output);
    } else if (finalize->parsed()) {
      const bool complete = aar::FinalizeManifest(finalize_dir);
      std::fprintf(stderr, "%s: manifest %s\n", finalize_dir.c_str(), complete ? "complete" : "incomplete (frames missing)");
      return complete ? 0 : 3;
    } else if (bench->parsed()) {
      RunBench(bench_flags.job, bench_levels, bench_pairs);
    } else if (devices->parsed()) {
      for (const aar::DeviceInfo& d : aar::VulkanContext::ListDevices()) {
        std::ostringstream counts;
        for (int c : d.color_sample_counts) counts << (counts.tellp() > 0 ? "," : "") << c;
        std::printf("%s | %s | %s | Vulkan %s | MSAA native %s | standard sample locations %s\n", d.name.c_str(),
                    d.driver_name.c_str(), d.driver_info.c_str(), d.api_version.c_str(), counts.str().c_str(),
                    d.standard_sample_locations ? "yes" : "no");
      }
    }
  } catch (const aar::Error& e) {
    std::fprintf(stderr, "aar-render: error: %s\n", e.what());
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aar-render: internal error: %s\n", e.what());
    return 2;
  }
  return 0;
}
