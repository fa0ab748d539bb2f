#pragma once
// Per-frame pose-estimation records and their CSV file (docs/analysis.md).

#include <Eigen/Geometry>
#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "aar/analyzer/bop_metrics.h"
#include "aar/analyzer/pose_filter.h"
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
  int icp_iterations = 0;      ///< RegistrationResult::iterations
  bool icp_converged = false;  ///< RegistrationResult::converged
  double icp_rmse_m = 0.0;     ///< RegistrationResult::rmse_m [m]
  size_t icp_inliers = 0;      ///< RegistrationResult::num_inliers
  StageTimes times;            ///< stage timings [ms]
  /// The sensed cloud against the depth truth (datasets with --depth; zero points otherwise).
  StereoTruthStats stereo_truth;
  /// Datasets with the boom and the object mask: the fraction of the
  /// receiver's left-image silhouette the boom hides (ReceiverOccludedFraction).
  std::optional<double> receiver_occluded_fraction;
  /// The temporal filter's pose (FilterFrameResults) and its error against the
  /// truth; none where the frame is not ok.
  std::optional<Pose> filtered;
  SixDof filtered_error;
  /// The estimate's BOP errors and ADD / ADD-S against the truth in the left
  /// camera (bop_metrics.h); where the frame has an estimate.
  std::optional<PoseErrorMetrics> bop_errors;

  /// An estimate exists (ok, or registered but rejected, e.g. by the
  /// residual test); est_* and err_* are then written even when not ok.
  bool has_estimate = false;

  bool ok() const { return status == "ok"; }
};

/// The CSV header (one line, no newline). The filter's columns filt_est_* and
/// filt_err_* follow the depth-truth columns, then the BOP errors mssd_m,
/// mspd_px, add_m, adds_m; the timing columns ms_* come after the first 50,
/// so that `cut -d, -f1-50` drops them for comparisons;
/// with `boom`, one more column receiver_occluded_fraction ends the line.
std::string FrameResultsCsvHeader(bool boom = false);

/// Header and one line per frame, in the given order. Fixed decimals
/// (aar::FormatFixed): 6 for seconds, metres and degrees, 3 for milliseconds.
/// est_* and err_* are empty for frames that are not ok (and have no
/// estimate), filt_est_* and filt_err_* for frames without a filtered pose,
/// the BOP errors for frames without them. The column
/// receiver_occluded_fraction is written when any frame has the value (empty
/// where a frame has none).
std::string FormatFrameResults(const std::vector<FrameResult>& results);

/// Parses FormatFrameResults's text; `where` (a file name) prefixes errors,
/// which name the line and column.
std::vector<FrameResult> ParseFrameResults(std::string_view text, const std::string& where);

/// The ok frames' estimates as a BOP results file (bop_toolkit's CSV:
/// header `scene_id,im_id,obj_id,score,R,t,time`; scene 1, image = frame
/// index, object 1, as `aar-analyze export --format bop` numbers them; score
/// 1; R row-major and t in mm, space-separated, of camera_from_tanker *
/// estimate; time the frame's total in seconds, -1 where it is 0).
std::string FormatBopResults(const std::vector<FrameResult>& results, const Eigen::Isometry3d& camera_from_tanker);

/// Atomic write / read of a results CSV; errors name the file.
void WriteFrameResults(const std::filesystem::path& path, const std::vector<FrameResult>& results);
std::vector<FrameResult> ReadFrameResults(const std::filesystem::path& path);

/// Sets every frame's filtered pose and error: FilterPoses over the ok frames'
/// estimates in the given order (frame order), each value quantised as the CSV
/// stores it first, so that filtering the frames read back from a CSV (a
/// merge) gives the same result as filtering them in the run.
void FilterFrameResults(std::vector<FrameResult>& frames, const PoseFilterOptions& options);

/// Concatenates per-shard results sorted by frame index. Throws aar::Error
/// naming the frame and both shards (by `shard_names` when given, else by
/// position) when a frame appears twice.
std::vector<FrameResult> MergeFrameResults(const std::vector<std::vector<FrameResult>>& shards,
                                           const std::vector<std::string>& shard_names = {});

}  // namespace aar
