#pragma once
// The thesis's statistics over per-frame records (frame_results.h) (section 3.7, chapter IV): mean absolute error and
// RMS error (equation 4) of each degree of freedom per region (A, B, C; Tables 4-5) and per range bin (20-60 m, 60-110
// m; Tables 1-2), and ICP execution time mean and standard deviation (Table 3).

#include <array>
#include <cstddef>
#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "aar/analyzer/bop_metrics.h"
#include "aar/analyzer/frame_results.h"

namespace aar {

/// Statistics of one group of frames.
struct GroupStats {
  std::string group;                 ///< "all", "A", "B", "C", "20-60" or "60-110"
  size_t frames = 0;                 ///< frames in the group
  size_t ok = 0;                     ///< frames with an estimate
  size_t failed = 0;                 ///< frames without
  SixDof mean_abs_error;             ///< mean |error| over ok frames
  SixDof rms_error;                  ///< sqrt(sum error^2 / n) over ok frames (thesis eq. 4)
  double sensed_points_mean = 0.0;   ///< over ok frames
  double icp_iterations_mean = 0.0;  ///< over ok frames
  size_t icp_converged = 0;          ///< ok frames whose ICP met a tolerance
  double icp_rmse_m_mean = 0.0;      ///< over ok frames [m]
  double icp_ms_mean = 0.0;          ///< ICP time, mean over ok frames [ms] (timing)
  double icp_ms_std = 0.0;           ///< ICP time, sample standard deviation (n-1) [ms] (timing)
  double total_ms_mean = 0.0;        ///< frame time, mean over all frames of the group [ms] (timing)
  /// Error of the frames that have an estimate, whatever their status
  /// (the thesis's convention: a frame whose ICP failed counts with its error).
  size_t with_estimate = 0;
  SixDof mean_abs_error_all;
  StereoTruthStats stereo_truth;  ///< summed over all frames of the group
  /// The temporal filter (pose_filter.h) over the ok frames.
  SixDof filtered_mean_abs_error;
  SixDof filtered_rms_error;
  /// Jitter: RMS of the change of the error from the previous analyzed frame to
  /// this one, over the frames of the group that are ok and follow an ok frame
  /// (`jitter_pairs` of them); the truth's own motion cancels, the noise stays
  /// (white noise of standard deviation s gives s sqrt 2).
  size_t jitter_pairs = 0;
  SixDof jitter_rms;
  SixDof filtered_jitter_rms;
  /// BOP scores and ADD / ADD-S recall over all frames of the group (a frame
  /// that is not ok is a miss; bop_metrics.h); with a BopScale only.
  std::optional<BopScores> bop;
};

/// All groups of one reference model, in the fixed order all, A, B, C, 20-60, 60-110.
struct ModelSummary {
  std::string model;  ///< "full", "shelled", ...
  std::vector<GroupStats> groups;
};

struct Summary {
  std::vector<ModelSummary> models;  ///< in the order given
};

/// Groups frames by RegionForRange(range_m) and RangeBinForRange(range_m)
/// (recomputed from the range, so the region column cannot disagree).
/// Frames are sorted by index and every value is quantised exactly as the CSV
/// stores it before summing, so the summary of merged shard CSVs equals, bit
/// for bit, the summary of one run over the same frames. With `bop`, each
/// group also gets its BOP scores from the frames' bop_errors.
ModelSummary SummarizeFrames(const std::string& model, const std::vector<FrameResult>& frames,
                             const std::optional<BopScale>& bop = std::nullopt);

/// summary.json: {"schema": "aar-summary/1", "models": {model: {group: stats}},
/// (stats include filtered_mean_abs_error, filtered_rms_error, jitter_pairs,
/// jitter_rms, filtered_jitter_rms, and with BOP scores "bop": {targets,
/// ar_mssd, ar_mspd, ar_mssd_mspd, add_recall, adds_recall})
/// "timing": {model: {group: {icp_ms_mean, icp_ms_std, total_ms_mean}}}}.
/// Everything outside "timing" is deterministic; statistics of groups with no
/// ok frame are null.
nlohmann::json SummaryToJson(const Summary& summary);

/// Markdown tables in the thesis's layout: mean absolute error and RMS error
/// per range bin (Tables 1, 2) and per region (Tables 4, 5), rows = models
/// (plus "Difference (%)" = (full - shelled) / full when both are present),
/// columns X (m) Y (m) Z (m) Roll (deg) Pitch (deg) Yaw (deg); then ICP time
/// mean and standard deviation per range bin (Table 3) last; before it, the
/// temporal filter's table per region (mean absolute error and jitter, per
/// frame and filtered), and the BOP scores per region where computed.
std::string SummaryToMarkdown(const Summary& summary);

}  // namespace aar
