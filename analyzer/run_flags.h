#pragma once
// The flags of `aar-analyze run` and `bench` (and the reference-model flags
// `reference` shares), and how they resolve into the analysis's options.

#include <CLI/CLI.hpp>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "aar/analyzer/analysis_run.h"

namespace aar::cli {

// The dataset folder's own name ("." and "dir/" name the folder they mean).
std::string DatasetName(const std::filesystem::path& dataset);

// Reference-model flags shared by `reference`, `run` and `bench`.
struct ReferenceFlags {
  std::string shell = "strict";
  std::optional<std::string> cameras;
  std::optional<double> tolerance_m;
  size_t points = aar::ReferenceModelOptions{}.num_points;

  void Add(CLI::App* cmd);
  aar::ReferenceModelOptions Resolve() const;
};

// Flags of `run` and `bench`. Values a preset sets are optional: given, they
// override the preset.
struct RunFlags {
  aar::AnalysisRunOptions options;
  ReferenceFlags reference;
  std::string preset = "default";
  std::string calibration, receiver, frames, shard, disparity = "bm";
  std::optional<std::string> subpixel_window;
  std::optional<std::string> subpixel_interpolation;
  std::optional<bool> window_bias;
  std::optional<std::string> direct, seed, registration, correspondence, pairing, residual;
  std::optional<int> icp_iterations, num_disparities, block_size, halo_radius, uniqueness_ratio, speckle_window;
  std::optional<double> direct_max_motion_px, max_correspondence_m, disparity_offset_px, disparity_noise_px,
      gate_sigmas, model_pull_scale_m;
  std::optional<size_t> keep_one_in, target_points, model_queries;
  std::optional<bool> halo, clipped, subpixel, rounding, widen, balance, full_surface, noise_bias;
  bool truth_cloud = false, track = false, mask_boom = false, no_mask_boom = false, mask_propellers = false,
       no_mask_propellers = false;
  double truth_cloud_noise_px = 0.0;
  int boom_margin_px = aar::BoomMaskOptions{}.margin_px;
  std::vector<size_t> dump_frames;
  std::string options_from;  // a run folder whose run.json's options replace the analysis flags
  CLI::App* cmd = nullptr;   // the command Add declared the flags on

  void Add(CLI::App* cmd);
  void AddRegistration(CLI::App* cmd);
  void AddStereo(CLI::App* cmd);
  void AddMasksAndDiagnosis(CLI::App* cmd);
  // `run` only: per listed frame, disparity, clouds and overlay into OUT/frames/.
  void AddDump(CLI::App* cmd);

  void Resolve();
  // --options-from: refuses the analysis flags, then takes the options the run folder's run.json records.
  void ApplyOptionsFrom();
};

}  // namespace aar::cli
