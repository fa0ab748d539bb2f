#pragma once
// Per-frame pose-estimation records, their CSV file, and the thesis's
// statistics (section 3.7, chapter IV): mean absolute error and RMS error
// (equation 4) of each degree of freedom per region (A, B, C; Tables 4-5)
// and per range bin (20-60 m, 60-110 m; Tables 1-2), and ICP execution time
// mean and standard deviation (Table 3).

#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "aar/analyzer/stereo_truth.h"
#include "aar/pose.h"

namespace aar {

/// Six values in the thesis's column order: X, Y, Z [m], roll, pitch, yaw [deg].
struct SixDof {
  std::array<double, 6> values{};  ///< x_m, y_m, z_m, roll_deg, pitch_deg, yaw_deg
  double& operator[](size_t i) { return values[i]; }
  double operator[](size_t i) const { return values[i]; }
};

/// Column suffixes of the six degrees of freedom.
inline constexpr std::array<const char*, 6> kDofNames = {"x_m", "y_m", "z_m", "roll_deg", "pitch_deg", "yaw_deg"};

/// x, y, z, roll, pitch, yaw of a pose as six values.
SixDof PoseValues(const Pose& pose);

/// estimate - truth per degree of freedom, angle differences wrapped to (-180, 180].
SixDof PoseError(const Pose& estimate, const Pose& truth);

/// Wall-clock milliseconds of the pipeline stages of one frame.
struct StageTimes {
  double load_ms = 0.0;       ///< reading the image pair [ms]
  double rectify_ms = 0.0;    ///< rectification [ms]
  double disparity_ms = 0.0;  ///< stereo block matching [ms]
  double reproject_ms = 0.0;  ///< re-projection, filtering, decimation, to tanker frame [ms]
  double icp_ms = 0.0;        ///< seeding and ICP [ms]
  double total_ms = 0.0;      ///< the whole frame [ms]
};

/// One frame of one run (one reference model).
struct FrameResult {
  size_t frame = 0;             ///< frame index in the dataset
  double time_s = 0.0;          ///< flight-path time [s]
  std::string region = "none";  ///< RegionForRange(range_m), as recorded
  double range_m = 0.0;         ///< left camera centre to receiver reference point [m]
  /// "ok", or why the frame has no estimate (e.g. "too few sensed points").
  /// Commas and line breaks are replaced by ';' and ' ' when written.
  std::string status = "ok";
  Pose truth;                  ///< true tanker_from_receiver
  Pose estimate;               ///< estimated tanker_from_receiver (meaningful when ok)
  SixDof error;                ///< PoseError(estimate, truth) (meaningful when ok)
  size_t sensed_points = 0;    ///< points of the sensed cloud given to ICP
  int icp_iterations = 0;      ///< IcpResult::iterations
  bool icp_converged = false;  ///< IcpResult::converged
  double icp_rmse_m = 0.0;     ///< IcpResult::rmse_m [m]
  size_t icp_inliers = 0;      ///< IcpResult::num_inliers
  StageTimes times;            ///< stage timings [ms]
  /// The sensed cloud against the depth truth (datasets with --depth; zero points otherwise).
  StereoTruthStats stereo_truth;

  /// An estimate exists (ok, or registered but rejected, e.g. by the
  /// residual test); est_* and err_* are then written even when not ok.
  bool has_estimate = false;

  bool ok() const { return status == "ok"; }
};

/// The CSV header (one line, no newline). The timing columns ms_* come last
/// so that `cut -d, -f1-34` drops them for comparisons.
std::string FrameResultsCsvHeader();

/// Header and one line per frame, in the given order. Fixed decimals
/// (aar::FormatFixed): 6 for seconds, metres and degrees, 3 for milliseconds.
/// est_* and err_* are empty for frames that are not ok.
std::string FormatFrameResults(const std::vector<FrameResult>& results);

/// Parses FormatFrameResults's text; `where` (a file name) prefixes errors,
/// which name the line and column.
std::vector<FrameResult> ParseFrameResults(std::string_view text, const std::string& where);

/// Atomic write / read of a results CSV; errors name the file.
void WriteFrameResults(const std::filesystem::path& path, const std::vector<FrameResult>& results);
std::vector<FrameResult> ReadFrameResults(const std::filesystem::path& path);

/// Concatenates per-shard results sorted by frame index. Throws aar::Error
/// naming the frame and both shards (by `shard_names` when given, else by
/// position) when a frame appears twice.
std::vector<FrameResult> MergeFrameResults(const std::vector<std::vector<FrameResult>>& shards,
                                           const std::vector<std::string>& shard_names = {});

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
  StereoTruthStats stereo_truth;     ///< summed over all frames of the group
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
/// for bit, the summary of one run over the same frames.
ModelSummary SummarizeFrames(const std::string& model, const std::vector<FrameResult>& frames);

/// summary.json: {"schema": "aar-summary/1", "models": {model: {group: stats}},
/// "timing": {model: {group: {icp_ms_mean, icp_ms_std, total_ms_mean}}}}.
/// Everything outside "timing" is deterministic; statistics of groups with no
/// ok frame are null.
nlohmann::json SummaryToJson(const Summary& summary);

/// Markdown tables in the thesis's layout: mean absolute error and RMS error
/// per range bin (Tables 1, 2) and per region (Tables 4, 5), rows = models
/// (plus "Difference (%)" = (full - shelled) / full when both are present),
/// columns X (m) Y (m) Z (m) Roll (deg) Pitch (deg) Yaw (deg); then ICP time
/// mean and standard deviation per range bin (Table 3) last.
std::string SummaryToMarkdown(const Summary& summary);

}  // namespace aar
