#include "aar/analyzer/frame_results.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <string>

#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/text.h"

namespace aar {
namespace {

constexpr int kValueDecimals = 6;     // seconds, metres, degrees
constexpr int kTimeDecimals = 3;      // milliseconds
constexpr size_t kColumns = 59;       // 60 with receiver_occluded_fraction
constexpr size_t kFilterColumn = 34;  // first filt_est_* column
constexpr size_t kBopColumn = 46;     // mssd_m, then mspd_px, add_m, adds_m, vsd_errors
constexpr size_t kVsdColumn = kBopColumn + 4;

const std::array<const char*, 4> kBopColumns = {"mssd_m", "mspd_px", "add_m", "adds_m"};

std::array<double*, 4> BopFields(PoseErrorMetrics& m) { return {&m.mssd_m, &m.mspd_px, &m.add_m, &m.adds_m}; }

const std::array<const char*, 6> kTimeColumns = {"ms_load",      "ms_rectify", "ms_disparity",
                                                 "ms_reproject", "ms_icp",     "ms_total"};

std::array<double*, 6> TimeFields(StageTimes& t) {
  return {&t.load_ms, &t.rectify_ms, &t.disparity_ms, &t.reproject_ms, &t.icp_ms, &t.total_ms};
}

Pose PoseFromValues(const SixDof& v) {
  Pose pose;
  pose.translation_m = Eigen::Vector3d(v[0], v[1], v[2]);
  pose.roll_deg = v[3];
  pose.pitch_deg = v[4];
  pose.yaw_deg = v[5];
  return pose;
}

std::string CleanStatus(const std::string& status) {
  std::string s = status.empty() ? std::string("failed") : status;
  for (char& c : s) {
    if (c == ',') c = ';';
    if (c == '\n' || c == '\r') c = ' ';
  }
  return s;
}

// Names a column (0-based index) of one CSV line in errors: "file:line column N".
struct ColumnName {
  std::string at;
  std::string operator()(size_t i) const { return at + " column " + std::to_string(i + 1); }
};

// frame, time_s, region, range_m and status.
void ParseFrameColumns(const std::vector<std::string>& fields, const ColumnName& column, FrameResult& f) {
  f.frame = static_cast<size_t>(ParseInteger(fields[0], column(0)));
  f.time_s = ParseFiniteDouble(fields[1], column(1));
  f.region = fields[2];
  if (f.region != "A" && f.region != "B" && f.region != "C" && f.region != "none") {
    throw Error(column(2) + ": region '" + f.region + "' is not A, B, C or none");
  }
  f.range_m = ParseFiniteDouble(fields[3], column(3));
  f.status = fields[4];
  if (f.status.empty()) throw Error(column(4) + ": empty status");
}

// truth_*, est_* and err_*: the estimate and error only for a measured frame
// or where they are not empty.
void ParsePoseColumns(const std::vector<std::string>& fields, const ColumnName& column, FrameResult& f) {
  SixDof truth, estimate;
  for (size_t d = 0; d < 6; ++d) {
    truth[d] = ParseFiniteDouble(fields[5 + d], column(5 + d));
    const bool empty = fields[11 + d].empty() && fields[17 + d].empty();
    if (f.ok() || !empty) {
      f.has_estimate = true;
      estimate[d] = ParseFiniteDouble(fields[11 + d], column(11 + d));
      f.error[d] = ParseFiniteDouble(fields[17 + d], column(17 + d));
    }
  }
  f.truth = PoseFromValues(truth);
  f.estimate = PoseFromValues(estimate);
}

// sensed_points and the icp_* columns.
void ParseIcpColumns(const std::vector<std::string>& fields, const ColumnName& column, FrameResult& f) {
  f.sensed_points = static_cast<size_t>(ParseInteger(fields[23], column(23)));
  f.icp_iterations = static_cast<int>(ParseInteger(fields[24], column(24)));
  if (fields[25] != "0" && fields[25] != "1") throw Error(column(25) + ": icp_converged must be 0 or 1");
  f.icp_converged = fields[25] == "1";
  f.icp_rmse_m = ParseFiniteDouble(fields[26], column(26));
  f.icp_inliers = static_cast<size_t>(ParseInteger(fields[27], column(27)));
}

// truth_points to truth_error_by_fraction (the propeller counts come later).
void ParseStereoTruthColumns(const std::vector<std::string>& fields, const ColumnName& column, StereoTruthStats& t) {
  t.points = static_cast<size_t>(ParseInteger(fields[28], column(28)));
  t.off_receiver = static_cast<size_t>(ParseInteger(fields[29], column(29)));
  t.off_surface = static_cast<size_t>(ParseInteger(fields[30], column(30)));
  t.error_sum_px = ParseFiniteDouble(fields[31], column(31));
  t.error_squared_sum_px2 = ParseFiniteDouble(fields[32], column(32));
  std::istringstream bins(fields[33]);
  std::string item;
  size_t b = 0;
  for (; b < kFractionBins && bins >> item; ++b) {
    const size_t slash = item.find('/');
    if (slash == std::string::npos) throw Error(column(33) + ": expected count/sum pairs");
    t.bin_count[b] = static_cast<size_t>(ParseInteger(item.substr(0, slash), column(33)));
    t.bin_error_sum_px[b] = ParseFiniteDouble(item.substr(slash + 1), column(33));
    t.on_receiver += t.bin_count[b];
  }
  if (b != kFractionBins || bins >> item) throw Error(column(33) + ": expected 8 count/sum pairs");
}

// filt_est_* and filt_err_*: all empty without a filtered pose.
void ParseFilteredColumns(const std::vector<std::string>& fields, const ColumnName& column, FrameResult& f) {
  const bool empty = std::all_of(fields.begin() + kFilterColumn, fields.begin() + kFilterColumn + 12,
                                 [](const std::string& v) { return v.empty(); });
  if (empty) return;
  SixDof filtered;
  for (size_t d = 0; d < 6; ++d) {
    filtered[d] = ParseFiniteDouble(fields[kFilterColumn + d], column(kFilterColumn + d));
    f.filtered_error[d] = ParseFiniteDouble(fields[kFilterColumn + 6 + d], column(kFilterColumn + 6 + d));
  }
  f.filtered = PoseFromValues(filtered);
}

// mssd_m to adds_m, then vsd_errors (only with them).
void ParseBopColumns(const std::vector<std::string>& fields, const ColumnName& column, FrameResult& f) {
  if (std::any_of(fields.begin() + kBopColumn, fields.begin() + kBopColumn + 4,
                  [](const std::string& v) { return !v.empty(); })) {
    PoseErrorMetrics bop;
    size_t c = kBopColumn;
    for (double* v : BopFields(bop)) {
      *v = ParseFiniteDouble(fields[c], column(c));
      ++c;
    }
    f.bop_errors = bop;
  }
  if (!fields[kVsdColumn].empty()) {
    if (!f.bop_errors) throw Error(column(kVsdColumn) + ": vsd_errors without the other pose errors");
    std::istringstream items(fields[kVsdColumn]);
    std::string item;
    VsdErrors vsd;
    size_t t = 0;
    for (; t < vsd.size() && items >> item; ++t) vsd[t] = ParseFiniteDouble(item, column(kVsdColumn));
    if (t != vsd.size() || items >> item) {
      throw Error(column(kVsdColumn) + ": expected " + std::to_string(vsd.size()) + " VSD errors");
    }
    f.bop_errors->vsd = vsd;
  }
}

// One data line, split into its columns (as many as the header has), in
// column order; `at` is "file:line".
FrameResult ParseFrameResultLine(const std::vector<std::string>& fields, const std::string& at, bool boom) {
  const ColumnName column{at};
  FrameResult f;
  ParseFrameColumns(fields, column, f);
  ParsePoseColumns(fields, column, f);
  ParseIcpColumns(fields, column, f);
  ParseStereoTruthColumns(fields, column, f.stereo_truth);
  ParseFilteredColumns(fields, column, f);
  ParseBopColumns(fields, column, f);
  StereoTruthStats& t = f.stereo_truth;
  t.on_propellers = static_cast<size_t>(ParseInteger(fields[kVsdColumn + 1], column(kVsdColumn + 1)));
  t.propellers_kept = static_cast<size_t>(ParseInteger(fields[kVsdColumn + 2], column(kVsdColumn + 2)));
  size_t c = kVsdColumn + 3;
  for (double* t : TimeFields(f.times)) {
    *t = ParseFiniteDouble(fields[c], column(c));
    ++c;
  }
  if (boom && !fields[c].empty()) f.receiver_occluded_fraction = ParseFiniteDouble(fields[c], column(c));
  return f;
}

}  // namespace

SixDof PoseValues(const Pose& pose) {
  SixDof v;
  v.values = {pose.translation_m.x(), pose.translation_m.y(), pose.translation_m.z(),
              pose.roll_deg,          pose.pitch_deg,         pose.yaw_deg};
  return v;
}

SixDof PoseError(const Pose& estimate, const Pose& truth) {
  const SixDof e = PoseValues(estimate);
  const SixDof t = PoseValues(truth);
  SixDof error;
  for (size_t d = 0; d < 6; ++d) error[d] = d < 3 ? e[d] - t[d] : WrapDegrees(e[d] - t[d]);
  return error;
}

std::string FrameResultsCsvHeader(bool boom) {
  std::string h = "frame,time_s,region,range_m,status";
  for (const char* prefix : {"truth_", "est_", "err_"}) {
    for (const char* dof : kDofNames) h += std::string(",") + prefix + dof;
  }
  h += ",sensed_points,icp_iterations,icp_converged,icp_rmse_m,icp_inliers";
  h += ",truth_points,truth_off_receiver,truth_off_surface,truth_error_sum_px,truth_error_squared_sum_px2,"
       "truth_error_by_fraction";
  for (const char* prefix : {"filt_est_", "filt_err_"}) {
    for (const char* dof : kDofNames) h += std::string(",") + prefix + dof;
  }
  for (const char* column : kBopColumns) h += std::string(",") + column;
  h += ",vsd_errors,truth_on_propellers,truth_propellers_kept";
  for (const char* column : kTimeColumns) h += std::string(",") + column;
  if (boom) h += ",receiver_occluded_fraction";
  return h;
}

std::string FormatFrameResults(const std::vector<FrameResult>& results) {
  const bool boom = std::any_of(results.begin(), results.end(),
                                [](const FrameResult& f) { return f.receiver_occluded_fraction.has_value(); });
  std::string out = FrameResultsCsvHeader(boom);
  out += '\n';
  const auto field = [&out](const std::string& text) {
    out += ',';
    out += text;
  };
  for (const FrameResult& f : results) {
    out += std::to_string(f.frame);
    field(FormatFixed(f.time_s, kValueDecimals));
    field(f.region);
    field(FormatFixed(f.range_m, kValueDecimals));
    field(CleanStatus(f.status));
    const SixDof truth = PoseValues(f.truth);
    const SixDof estimate = PoseValues(f.estimate);
    for (const SixDof* v : {&truth, &estimate, &f.error}) {
      for (size_t d = 0; d < 6; ++d) {
        field(v == &truth || f.ok() || f.has_estimate ? FormatFixed((*v)[d], kValueDecimals) : std::string());
      }
    }
    field(std::to_string(f.sensed_points));
    field(std::to_string(f.icp_iterations));
    field(f.icp_converged ? "1" : "0");
    field(FormatFixed(f.icp_rmse_m, kValueDecimals));
    field(std::to_string(f.icp_inliers));
    const StereoTruthStats& t = f.stereo_truth;
    field(std::to_string(t.points));
    field(std::to_string(t.off_receiver));
    field(std::to_string(t.off_surface));
    field(FormatFixed(t.error_sum_px, kValueDecimals));
    field(FormatFixed(t.error_squared_sum_px2, kValueDecimals));
    std::string bins;
    for (size_t b = 0; b < kFractionBins; ++b) {
      bins +=
          (b ? " " : "") + std::to_string(t.bin_count[b]) + "/" + FormatFixed(t.bin_error_sum_px[b], kValueDecimals);
    }
    field(bins);
    const SixDof filtered = f.filtered ? PoseValues(*f.filtered) : SixDof{};
    for (const SixDof* v : {&filtered, &f.filtered_error}) {
      for (size_t d = 0; d < 6; ++d) field(f.filtered ? FormatFixed((*v)[d], kValueDecimals) : std::string());
    }
    PoseErrorMetrics bop = f.bop_errors.value_or(PoseErrorMetrics{});
    for (const double* v : BopFields(bop)) field(f.bop_errors ? FormatFixed(*v, kValueDecimals) : std::string());
    std::string vsd;
    if (bop.vsd) {
      for (double e : *bop.vsd) vsd += (vsd.empty() ? "" : " ") + FormatFixed(e, kValueDecimals);
    }
    field(vsd);
    field(std::to_string(t.on_propellers));
    field(std::to_string(t.propellers_kept));
    StageTimes times = f.times;
    for (const double* t : TimeFields(times)) field(FormatFixed(*t, kTimeDecimals));
    if (boom) {
      field(f.receiver_occluded_fraction ? FormatFixed(*f.receiver_occluded_fraction, kValueDecimals) : std::string());
    }
    out += '\n';
  }
  return out;
}

std::vector<FrameResult> ParseFrameResults(std::string_view text, const std::string& where) {
  std::vector<FrameResult> results;
  size_t pos = 0;
  bool header_seen = false;
  bool boom = false;
  for (size_t line_number = 1; pos < text.size(); ++line_number) {
    const size_t newline = text.find('\n', pos);
    const std::string line =
        TrimCr(text.substr(pos, newline == std::string_view::npos ? std::string_view::npos : newline - pos));
    pos = newline == std::string_view::npos ? text.size() : newline + 1;
    const std::string at = where + ":" + std::to_string(line_number);
    if (!header_seen) {
      boom = line == FrameResultsCsvHeader(true);
      if (line != FrameResultsCsvHeader() && !boom) throw Error(at + ": not a frame-results CSV (unexpected header)");
      header_seen = true;
      continue;
    }
    if (line.empty()) continue;
    const std::vector<std::string> fields = SplitCsvLine(line);
    const size_t columns = kColumns + (boom ? 1 : 0);
    if (fields.size() != columns) {
      throw Error(at + ": expected " + std::to_string(columns) + " columns, found " + std::to_string(fields.size()));
    }
    results.push_back(ParseFrameResultLine(fields, at, boom));
  }
  if (!header_seen) throw Error(where + ": empty file (no header)");
  return results;
}

std::string FormatBopResults(const std::vector<FrameResult>& results, const Eigen::Isometry3d& camera_from_tanker) {
  std::string out = "scene_id,im_id,obj_id,score,R,t,time\n";
  for (const FrameResult& f : results) {
    if (!f.ok()) continue;
    const Eigen::Isometry3d cam_from_receiver = camera_from_tanker * IsometryFromPose(f.estimate);
    std::string r, t;
    for (int i = 0; i < 3; ++i) {
      for (int k = 0; k < 3; ++k) r += (r.empty() ? "" : " ") + FormatFixed(cam_from_receiver.linear()(i, k), 9);
      t += (i ? " " : "") + FormatFixed(cam_from_receiver.translation()(i) * 1000.0, kValueDecimals);
    }
    const double time_s = f.times.total_ms > 0.0 ? f.times.total_ms / 1000.0 : -1.0;
    out += "1," + std::to_string(f.frame) + ",1,1," + r + "," + t + "," + FormatFixed(time_s, 6) + "\n";
  }
  return out;
}

void WriteFrameResults(const std::filesystem::path& path, const std::vector<FrameResult>& results) {
  WriteFileAtomic(path, FormatFrameResults(results));
}

std::vector<FrameResult> ReadFrameResults(const std::filesystem::path& path) {
  return ParseFrameResults(ReadFileBytes(path), path.string());
}

void FilterFrameResults(std::vector<FrameResult>& frames, const PoseFilterOptions& options) {
  const auto quantised = [](double value) { return ParseFiniteDouble(FormatFixed(value, kValueDecimals), "filter"); };
  const auto quantised_pose = [&](const Pose& pose) {
    SixDof values = PoseValues(pose);
    for (double& v : values.values) v = quantised(v);
    return PoseFromValues(values);
  };
  std::vector<TimedPose> sequence;
  sequence.reserve(frames.size());
  for (const FrameResult& f : frames) {
    TimedPose timed;
    timed.time_s = quantised(f.time_s);
    if (f.ok()) timed.pose = quantised_pose(f.estimate);
    sequence.push_back(timed);
  }
  const std::vector<std::optional<Pose>> filtered = FilterPoses(sequence, options);
  for (size_t i = 0; i < frames.size(); ++i) {
    frames[i].filtered = filtered[i];
    frames[i].filtered_error = filtered[i] ? PoseError(*filtered[i], quantised_pose(frames[i].truth)) : SixDof{};
  }
}

std::vector<FrameResult> MergeFrameResults(const std::vector<std::vector<FrameResult>>& shards,
                                           const std::vector<std::string>& shard_names) {
  const auto name = [&](size_t shard) {
    return shard < shard_names.size() ? shard_names[shard] : "shard " + std::to_string(shard);
  };
  std::map<size_t, size_t> shard_of_frame;       // frame index -> shard
  std::vector<std::pair<size_t, size_t>> order;  // (shard, position)
  for (size_t s = 0; s < shards.size(); ++s) {
    for (size_t i = 0; i < shards[s].size(); ++i) {
      const auto [it, inserted] = shard_of_frame.emplace(shards[s][i].frame, s);
      if (!inserted) {
        throw Error("merge: frame " + std::to_string(shards[s][i].frame) + " appears in both " + name(it->second) +
                    " and " + name(s));
      }
      order.emplace_back(s, i);
    }
  }
  std::sort(order.begin(), order.end(), [&](const auto& a, const auto& b) {
    return shards[a.first][a.second].frame < shards[b.first][b.second].frame;
  });
  std::vector<FrameResult> merged;
  merged.reserve(order.size());
  for (const auto& [s, i] : order) merged.push_back(shards[s][i]);
  return merged;
}

}  // namespace aar
