#include "aar/analyzer/pose_statistics.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>

#include <nlohmann/json.hpp>

#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/region.h"
#include "aar/text.h"

namespace aar {
namespace {

constexpr int kValueDecimals = 6;  // seconds, metres, degrees
constexpr int kTimeDecimals = 3;   // milliseconds
constexpr size_t kColumns = 40;

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

const std::vector<std::string>& GroupNames() {
  static const std::vector<std::string> names = {"all", "A", "B", "C", "20-60", "60-110"};
  return names;
}

bool InGroup(const FrameResult& f, const std::string& group) {
  if (group == "all") return true;
  if (group == "A" || group == "B" || group == "C") return RegionForRange(f.range_m) == group;
  return RangeBinForRange(f.range_m) == group;
}

GroupStats Aggregate(const std::vector<FrameResult>& frames, const std::string& group) {
  GroupStats g;
  g.group = group;
  double icp_ms_sum = 0.0;
  double total_ms_sum = 0.0;
  std::vector<double> icp_ms;
  for (const FrameResult& f : frames) {  // frames are sorted by index: fixed summation order
    if (!InGroup(f, group)) continue;
    ++g.frames;
    total_ms_sum += f.times.total_ms;
    g.stereo_truth.Add(f.stereo_truth);
    if (f.ok() || f.has_estimate) {
      ++g.with_estimate;
      for (size_t d = 0; d < 6; ++d) g.mean_abs_error_all[d] += std::abs(f.error[d]);
    }
    if (!f.ok()) {
      ++g.failed;
      continue;
    }
    ++g.ok;
    for (size_t d = 0; d < 6; ++d) {
      g.mean_abs_error[d] += std::abs(f.error[d]);
      g.rms_error[d] += f.error[d] * f.error[d];
    }
    g.sensed_points_mean += static_cast<double>(f.sensed_points);
    g.icp_iterations_mean += f.icp_iterations;
    g.icp_converged += f.icp_converged ? 1 : 0;
    g.icp_rmse_m_mean += f.icp_rmse_m;
    icp_ms_sum += f.times.icp_ms;
    icp_ms.push_back(f.times.icp_ms);
  }
  if (g.frames > 0) g.total_ms_mean = total_ms_sum / static_cast<double>(g.frames);
  if (g.with_estimate > 0) {
    for (size_t d = 0; d < 6; ++d) g.mean_abs_error_all[d] /= static_cast<double>(g.with_estimate);
  }
  if (g.ok == 0) return g;
  const double n = static_cast<double>(g.ok);
  for (size_t d = 0; d < 6; ++d) {
    g.mean_abs_error[d] /= n;
    g.rms_error[d] = std::sqrt(g.rms_error[d] / n);  // thesis eq. 4
  }
  g.sensed_points_mean /= n;
  g.icp_iterations_mean /= n;
  g.icp_rmse_m_mean /= n;
  g.icp_ms_mean = icp_ms_sum / n;
  if (g.ok > 1) {
    double squares = 0.0;
    for (const double t : icp_ms) squares += (t - g.icp_ms_mean) * (t - g.icp_ms_mean);
    g.icp_ms_std = std::sqrt(squares / (n - 1.0));
  }
  return g;
}

nlohmann::json SixDofJson(const SixDof& v) {
  nlohmann::json j = nlohmann::json::object();
  for (size_t d = 0; d < 6; ++d) j[kDofNames[d]] = v[d];
  return j;
}

std::string DisplayName(const std::string& model) {
  if (model == "full") return "Full Model";
  if (model == "shelled") return "Shelled Model";
  return model;
}

const GroupStats* FindGroup(const ModelSummary& m, const std::string& group) {
  for (const GroupStats& g : m.groups) {
    if (g.group == group) return &g;
  }
  return nullptr;
}

// Appends " text |" to a Markdown row.
void AppendCell(std::string& out, const std::string& text) {
  if (!text.empty()) {
    out += ' ';
    out += text;
  }
  out += " |";
}

// One thesis-style table: per group, one row per model, then the difference row.
std::string DofTable(const Summary& summary, const std::vector<std::string>& groups, const std::string& group_title,
                     bool rms) {
  std::string out = "| " + group_title +
                    " | Model | X (m) | Y (m) | Z (m) | Roll (deg) | Pitch (deg) | Yaw (deg) | Frames (ok/all) |\n"
                    "|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  const ModelSummary* full = nullptr;
  const ModelSummary* shelled = nullptr;
  for (const ModelSummary& m : summary.models) {
    if (m.model == "full") full = &m;
    if (m.model == "shelled") shelled = &m;
  }
  for (const std::string& group : groups) {
    const std::string label = (group == "A" || group == "B" || group == "C") ? group : group + " m";
    bool first = true;
    for (const ModelSummary& m : summary.models) {
      const GroupStats* g = FindGroup(m, group);
      if (g == nullptr) continue;
      out += "|";
      AppendCell(out, first ? label : std::string());
      AppendCell(out, DisplayName(m.model));
      first = false;
      for (size_t d = 0; d < 6; ++d) {
        AppendCell(out, g->ok == 0 ? std::string("n/a") : FormatFixed(rms ? g->rms_error[d] : g->mean_abs_error[d], 3));
      }
      AppendCell(out, std::to_string(g->ok) + "/" + std::to_string(g->frames));
      out += "\n";
    }
    if (!rms && full != nullptr && shelled != nullptr) {
      const GroupStats* f = FindGroup(*full, group);
      const GroupStats* s = FindGroup(*shelled, group);
      if (f == nullptr || s == nullptr) continue;
      out += "| | Difference (%) |";
      for (size_t d = 0; d < 6; ++d) {
        const bool valid = f->ok > 0 && s->ok > 0 && f->mean_abs_error[d] > 0.0;
        AppendCell(out,
                   valid ? FormatFixed(100.0 * (f->mean_abs_error[d] - s->mean_abs_error[d]) / f->mean_abs_error[d], 2)
                         : std::string("n/a"));
      }
      AppendCell(out, std::string());  // no frame count
      out += "\n";
    }
  }
  return out;
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

std::string FrameResultsCsvHeader() {
  std::string h = "frame,time_s,region,range_m,status";
  for (const char* prefix : {"truth_", "est_", "err_"}) {
    for (const char* dof : kDofNames) h += std::string(",") + prefix + dof;
  }
  h += ",sensed_points,icp_iterations,icp_converged,icp_rmse_m,icp_inliers";
  h += ",truth_points,truth_off_receiver,truth_off_surface,truth_error_sum_px,truth_error_squared_sum_px2,"
       "truth_error_by_fraction";
  for (const char* column : kTimeColumns) h += std::string(",") + column;
  return h;
}

std::string FormatFrameResults(const std::vector<FrameResult>& results) {
  std::string out = FrameResultsCsvHeader();
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
      bins += (b ? " " : "") + std::to_string(t.bin_count[b]) + "/" + FormatFixed(t.bin_error_sum_px[b], kValueDecimals);
    }
    field(bins);
    StageTimes times = f.times;
    for (const double* t : TimeFields(times)) field(FormatFixed(*t, kTimeDecimals));
    out += '\n';
  }
  return out;
}

std::vector<FrameResult> ParseFrameResults(std::string_view text, const std::string& where) {
  std::vector<FrameResult> results;
  size_t pos = 0;
  bool header_seen = false;
  for (size_t line_number = 1; pos < text.size(); ++line_number) {
    const size_t newline = text.find('\n', pos);
    const std::string line =
        TrimCr(text.substr(pos, newline == std::string_view::npos ? std::string_view::npos : newline - pos));
    pos = newline == std::string_view::npos ? text.size() : newline + 1;
    const std::string at = where + ":" + std::to_string(line_number);
    if (!header_seen) {
      if (line != FrameResultsCsvHeader()) throw Error(at + ": not a frame-results CSV (unexpected header)");
      header_seen = true;
      continue;
    }
    if (line.empty()) continue;
    const std::vector<std::string> fields = SplitCsvLine(line);
    if (fields.size() != kColumns) {
      throw Error(at + ": expected " + std::to_string(kColumns) + " columns, found " + std::to_string(fields.size()));
    }
    const auto column = [&](size_t i) { return at + " column " + std::to_string(i + 1); };
    FrameResult f;
    f.frame = static_cast<size_t>(ParseInteger(fields[0], column(0)));
    f.time_s = ParseFiniteDouble(fields[1], column(1));
    f.region = fields[2];
    if (f.region != "A" && f.region != "B" && f.region != "C" && f.region != "none") {
      throw Error(column(2) + ": region '" + f.region + "' is not A, B, C or none");
    }
    f.range_m = ParseFiniteDouble(fields[3], column(3));
    f.status = fields[4];
    if (f.status.empty()) throw Error(column(4) + ": empty status");
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
    f.sensed_points = static_cast<size_t>(ParseInteger(fields[23], column(23)));
    f.icp_iterations = static_cast<int>(ParseInteger(fields[24], column(24)));
    if (fields[25] != "0" && fields[25] != "1") throw Error(column(25) + ": icp_converged must be 0 or 1");
    f.icp_converged = fields[25] == "1";
    f.icp_rmse_m = ParseFiniteDouble(fields[26], column(26));
    f.icp_inliers = static_cast<size_t>(ParseInteger(fields[27], column(27)));
    StereoTruthStats& t = f.stereo_truth;
    t.points = static_cast<size_t>(ParseInteger(fields[28], column(28)));
    t.off_receiver = static_cast<size_t>(ParseInteger(fields[29], column(29)));
    t.off_surface = static_cast<size_t>(ParseInteger(fields[30], column(30)));
    t.error_sum_px = ParseFiniteDouble(fields[31], column(31));
    t.error_squared_sum_px2 = ParseFiniteDouble(fields[32], column(32));
    {
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
    size_t c = 34;
    for (double* t : TimeFields(f.times)) {
      *t = ParseFiniteDouble(fields[c], column(c));
      ++c;
    }
    results.push_back(std::move(f));
  }
  if (!header_seen) throw Error(where + ": empty file (no header)");
  return results;
}

void WriteFrameResults(const std::filesystem::path& path, const std::vector<FrameResult>& results) {
  WriteFileAtomic(path, FormatFrameResults(results));
}

std::vector<FrameResult> ReadFrameResults(const std::filesystem::path& path) {
  return ParseFrameResults(ReadFileBytes(path), path.string());
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

ModelSummary SummarizeFrames(const std::string& model, const std::vector<FrameResult>& frames) {
  std::vector<FrameResult> sorted = frames;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const FrameResult& a, const FrameResult& b) { return a.frame < b.frame; });
  // Quantise exactly as the CSV does, so shard merges reproduce single runs.
  const std::vector<FrameResult> quantised = ParseFrameResults(FormatFrameResults(sorted), "summary of " + model);
  ModelSummary summary;
  summary.model = model;
  for (const std::string& group : GroupNames()) summary.groups.push_back(Aggregate(quantised, group));
  return summary;
}

nlohmann::json SummaryToJson(const Summary& summary) {
  nlohmann::json models = nlohmann::json::object();
  nlohmann::json timing = nlohmann::json::object();
  for (const ModelSummary& m : summary.models) {
    nlohmann::json groups = nlohmann::json::object();
    nlohmann::json times = nlohmann::json::object();
    for (const GroupStats& g : m.groups) {
      const bool any = g.ok > 0;
      groups[g.group] = {
          {"frames", g.frames},
          {"ok", g.ok},
          {"failed", g.failed},
          {"mean_abs_error", any ? SixDofJson(g.mean_abs_error) : nlohmann::json(nullptr)},
          {"rms_error", any ? SixDofJson(g.rms_error) : nlohmann::json(nullptr)},
          {"sensed_points_mean", any ? nlohmann::json(g.sensed_points_mean) : nlohmann::json(nullptr)},
          {"icp_iterations_mean", any ? nlohmann::json(g.icp_iterations_mean) : nlohmann::json(nullptr)},
          {"icp_converged", g.icp_converged},
          {"icp_rmse_m_mean", any ? nlohmann::json(g.icp_rmse_m_mean) : nlohmann::json(nullptr)},
      };
      times[g.group] = {{"icp_ms_mean", any ? nlohmann::json(g.icp_ms_mean) : nlohmann::json(nullptr)},
                        {"icp_ms_std", any ? nlohmann::json(g.icp_ms_std) : nlohmann::json(nullptr)},
                        {"total_ms_mean", g.frames > 0 ? nlohmann::json(g.total_ms_mean) : nlohmann::json(nullptr)}};
    }
    models[m.model] = groups;
    timing[m.model] = times;
  }
  return {{"schema", "aar-summary/1"}, {"models", models}, {"timing", timing}};
}

std::string SummaryToMarkdown(const Summary& summary) {
  const std::vector<std::string> bins = {"20-60", "60-110"};
  const std::vector<std::string> regions = {"A", "B", "C"};
  std::string out;
  out += std::string("## Mean absolute 6DOF error by range (Table 1 layout)\n\n") +
         DofTable(summary, bins, "Range", false) + "\n";
  out += std::string("## RMS 6DOF error by range (Table 2 layout)\n\n") + DofTable(summary, bins, "Range", true) + "\n";
  out += std::string("## Mean absolute 6DOF error by region (Table 4 layout)\n\n") +
         DofTable(summary, regions, "Region", false) + "\n";
  out += std::string("## RMS 6DOF error by region (Table 5 layout)\n\n") + DofTable(summary, regions, "Region", true) +
         "\n";
  out += "## Every frame (mean absolute error of every frame with an estimate, measured or rejected)\n\n"
          "| Region | Model | X (m) | Y (m) | Z (m) | Roll (deg) | Pitch (deg) | Yaw (deg) | Frames (estimated/all) |\n"
          "|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const std::string& group : regions) {
    for (const ModelSummary& m : summary.models) {
      const GroupStats* g = FindGroup(m, group);
      if (g == nullptr) continue;
      out += "|";
      AppendCell(out, group);
      AppendCell(out, DisplayName(m.model));
      for (size_t d = 0; d < 6; ++d) {
        AppendCell(out, g->with_estimate == 0 ? std::string("n/a") : FormatFixed(g->mean_abs_error_all[d], 3));
      }
      AppendCell(out, std::to_string(g->with_estimate) + "/" + std::to_string(g->frames));
      out += "\n";
    }
  }
  out += "\n";
  bool any_truth = false;
  for (const ModelSummary& m : summary.models) {
    for (const GroupStats& g : m.groups) any_truth = any_truth || g.stereo_truth.points > 0;
  }
  if (any_truth) {
    out += "## The sensed cloud against depth truth\n\n"
           "| Region | Model | Points | Off the receiver | Off the surface (> 0.5 px) | Disparity error mean (px) | RMS (px) |\n"
           "|---|---|---:|---:|---:|---:|---:|\n";
    for (const std::string& group : regions) {
      for (const ModelSummary& m : summary.models) {
        const GroupStats* g = FindGroup(m, group);
        if (g == nullptr || g->stereo_truth.points == 0) continue;
        const StereoTruthStats& t = g->stereo_truth;
        const double n = static_cast<double>(t.points);
        out += "|";
        AppendCell(out, group);
        AppendCell(out, DisplayName(m.model));
        AppendCell(out, std::to_string(t.points));
        AppendCell(out, FormatFixed(100.0 * static_cast<double>(t.off_receiver) / n, 1) + " %");
        AppendCell(out, FormatFixed(100.0 * static_cast<double>(t.off_surface) / n, 1) + " %");
        AppendCell(out, FormatFixed(t.MeanErrorPx(), 4));
        AppendCell(out, FormatFixed(t.RmsErrorPx(), 4));
        out += "\n";
      }
    }
    out += "\n";
  }
  out +=
      "## ICP execution time by range (Table 3 layout; machine-dependent)\n\n"
      "| Range | Model | Average ICP time (ms) | Standard deviation (ms) | Frames (ok) |\n"
      "|---|---|---:|---:|---:|\n";
  for (const std::string& group : bins) {
    bool first = true;
    for (const ModelSummary& m : summary.models) {
      const GroupStats* g = FindGroup(m, group);
      if (g == nullptr) continue;
      out += "|";
      AppendCell(out, first ? group + " m" : std::string());
      AppendCell(out, DisplayName(m.model));
      AppendCell(out, g->ok > 0 ? FormatFixed(g->icp_ms_mean, 3) : std::string("n/a"));
      AppendCell(out, g->ok > 1 ? FormatFixed(g->icp_ms_std, 3) : std::string("n/a"));
      AppendCell(out, std::to_string(g->ok));
      out += "\n";
      first = false;
    }
  }
  return out;
}

}  // namespace aar
