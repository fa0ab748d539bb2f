#include "aar/analyzer/pose_statistics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <utility>

#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/region.h"
#include "aar/text.h"

namespace aar {
namespace {

const std::vector<std::string>& GroupNames() {
  static const std::vector<std::string> names = {"all", "A", "B", "C", "20-60", "60-110"};
  return names;
}

bool InGroup(const FrameResult& f, const std::string& group) {
  if (group == "all") return true;
  if (group == "A" || group == "B" || group == "C") return RegionForRange(f.range_m) == group;
  return RangeBinForRange(f.range_m) == group;
}

// The squared changes of the error from `previous` to `f`, per frame and filtered.
void AddJitter(GroupStats& g, const FrameResult& f, const FrameResult& previous) {
  for (size_t d = 0; d < 6; ++d) {
    const double change = f.error[d] - previous.error[d];
    g.jitter_rms[d] += change * change;
    if (f.filtered && previous.filtered) {
      const double filtered_change = f.filtered_error[d] - previous.filtered_error[d];
      g.filtered_jitter_rms[d] += filtered_change * filtered_change;
    }
  }
}

GroupStats Aggregate(const std::vector<FrameResult>& frames, const std::string& group,
                     const std::optional<BopScale>& bop) {
  GroupStats g;
  g.group = group;
  std::vector<std::optional<PoseErrorMetrics>> bop_errors;
  double icp_ms_sum = 0.0;
  double total_ms_sum = 0.0;
  std::vector<double> icp_ms;
  for (size_t i = 0; i < frames.size(); ++i) {  // frames are sorted by index: fixed summation order
    const FrameResult& f = frames[i];
    if (!InGroup(f, group)) continue;
    ++g.frames;
    bop_errors.push_back(f.ok() ? f.bop_errors : std::nullopt);
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
    if (f.filtered) {
      for (size_t d = 0; d < 6; ++d) {
        g.filtered_mean_abs_error[d] += std::abs(f.filtered_error[d]);
        g.filtered_rms_error[d] += f.filtered_error[d] * f.filtered_error[d];
      }
    }
    if (i > 0 && frames[i - 1].ok()) {
      const FrameResult& previous = frames[i - 1];
      ++g.jitter_pairs;
      AddJitter(g, f, previous);
    }
    g.sensed_points_mean += static_cast<double>(f.sensed_points);
    g.icp_iterations_mean += f.icp_iterations;
    g.icp_converged += f.icp_converged ? 1 : 0;
    g.icp_rmse_m_mean += f.icp_rmse_m;
    icp_ms_sum += f.times.icp_ms;
    icp_ms.push_back(f.times.icp_ms);
  }
  if (g.frames > 0) g.total_ms_mean = total_ms_sum / static_cast<double>(g.frames);
  if (bop) g.bop = ScoreBop(bop_errors, *bop);
  if (g.with_estimate > 0) {
    for (size_t d = 0; d < 6; ++d) g.mean_abs_error_all[d] /= static_cast<double>(g.with_estimate);
  }
  if (g.ok == 0) return g;
  const double n = static_cast<double>(g.ok);
  for (size_t d = 0; d < 6; ++d) {
    g.mean_abs_error[d] /= n;
    g.rms_error[d] = std::sqrt(g.rms_error[d] / n);  // thesis eq. 4
    g.filtered_mean_abs_error[d] /= n;
    g.filtered_rms_error[d] = std::sqrt(g.filtered_rms_error[d] / n);
    if (g.jitter_pairs > 0) {
      const double pairs = static_cast<double>(g.jitter_pairs);
      g.jitter_rms[d] = std::sqrt(g.jitter_rms[d] / pairs);
      g.filtered_jitter_rms[d] = std::sqrt(g.filtered_jitter_rms[d] / pairs);
    }
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

ModelSummary SummarizeFrames(const std::string& model, const std::vector<FrameResult>& frames,
                             const std::optional<BopScale>& bop) {
  std::vector<FrameResult> sorted = frames;
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const FrameResult& a, const FrameResult& b) { return a.frame < b.frame; });
  // Quantise exactly as the CSV does, so shard merges reproduce single runs.
  const std::vector<FrameResult> quantised = ParseFrameResults(FormatFrameResults(sorted), "summary of " + model);
  ModelSummary summary;
  summary.model = model;
  for (const std::string& group : GroupNames()) summary.groups.push_back(Aggregate(quantised, group, bop));
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
          {"filtered_mean_abs_error", any ? SixDofJson(g.filtered_mean_abs_error) : nlohmann::json(nullptr)},
          {"filtered_rms_error", any ? SixDofJson(g.filtered_rms_error) : nlohmann::json(nullptr)},
          {"jitter_pairs", g.jitter_pairs},
          {"jitter_rms", g.jitter_pairs > 0 ? SixDofJson(g.jitter_rms) : nlohmann::json(nullptr)},
          {"filtered_jitter_rms", g.jitter_pairs > 0 ? SixDofJson(g.filtered_jitter_rms) : nlohmann::json(nullptr)},
      };
      if (g.bop) {
        groups[g.group]["bop"] = {{"targets", g.bop->targets},       {"ar_mssd", g.bop->ar_mssd},
                                  {"ar_mspd", g.bop->ar_mspd},       {"ar_mssd_mspd", g.bop->ar_mssd_mspd},
                                  {"add_recall", g.bop->add_recall}, {"adds_recall", g.bop->adds_recall}};
        if (g.bop->ar_vsd) {
          groups[g.group]["bop"]["ar_vsd"] = *g.bop->ar_vsd;
          groups[g.group]["bop"]["ar"] = *g.bop->ar;
        }
      }
      times[g.group] = {{"icp_ms_mean", any ? nlohmann::json(g.icp_ms_mean) : nlohmann::json(nullptr)},
                        {"icp_ms_std", any ? nlohmann::json(g.icp_ms_std) : nlohmann::json(nullptr)},
                        {"total_ms_mean", g.frames > 0 ? nlohmann::json(g.total_ms_mean) : nlohmann::json(nullptr)}};
    }
    models[m.model] = groups;
    timing[m.model] = times;
  }
  return {{"schema", "aar-summary/1"}, {"models", models}, {"timing", timing}};
}

namespace {

// summary.md's depth-truth table (datasets rendered with --depth only).
std::string TruthTable(const Summary& summary, const std::vector<std::string>& regions) {
  std::string out;
  bool any_truth = false, any_blades = false;
  for (const ModelSummary& m : summary.models) {
    for (const GroupStats& g : m.groups) {
      any_truth = any_truth || g.stereo_truth.points > 0;
      any_blades = any_blades || g.stereo_truth.on_propellers > 0;
    }
  }
  if (any_truth) {
    out +=
        "## The sensed cloud against depth truth\n\n"
        "| Region | Model | Points | Off the receiver | Off the surface (> 0.5 px) |";
    out += any_blades ? " On propeller blades | Blades kept |" : "";
    out += " Disparity error mean (px) | RMS (px) |\n|---|---|---:|---:|---:|";
    out += any_blades ? "---:|---:|" : "";
    out += "---:|---:|\n";
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
        if (any_blades) {
          AppendCell(out, FormatFixed(100.0 * static_cast<double>(t.on_propellers) / n, 1) + " %");
          AppendCell(out, FormatFixed(100.0 * static_cast<double>(t.propellers_kept) / n, 1) + " %");
        }
        AppendCell(out, FormatFixed(t.MeanErrorPx(), 4));
        AppendCell(out, FormatFixed(t.RmsErrorPx(), 4));
        out += "\n";
      }
    }
    out += "\n";
  }
  return out;
}

// summary.md's temporal filter table.
std::string FilterTable(const Summary& summary, const std::vector<std::string>& regions) {
  std::string out;
  out +=
      "## The temporal filter by region (mean absolute error; jitter: RMS change of the error from one analyzed frame "
      "to the next)\n\n"
      "| Region | Model | | X (m) | Y (m) | Z (m) | Roll (deg) | Pitch (deg) | Yaw (deg) | Frames |\n"
      "|---|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const std::string& group : regions) {
    for (const ModelSummary& m : summary.models) {
      const GroupStats* g = FindGroup(m, group);
      if (g == nullptr || g->ok == 0) continue;
      const std::array<std::pair<const char*, const SixDof*>, 4> rows = {
          std::pair{"error, per frame", &g->mean_abs_error}, std::pair{"error, filtered", &g->filtered_mean_abs_error},
          std::pair{"jitter, per frame", &g->jitter_rms}, std::pair{"jitter, filtered", &g->filtered_jitter_rms}};
      for (size_t r = 0; r < rows.size(); ++r) {
        const bool jitter = r >= 2;
        if (jitter && g->jitter_pairs == 0) continue;
        out += "|";
        AppendCell(out, r == 0 ? group : std::string());
        AppendCell(out, r == 0 ? DisplayName(m.model) : std::string());
        AppendCell(out, rows[r].first);
        for (size_t d = 0; d < 6; ++d) AppendCell(out, FormatFixed((*rows[r].second)[d], 3));
        AppendCell(out, std::to_string(jitter ? g->jitter_pairs : g->ok));
        out += "\n";
      }
    }
  }
  out += "\n";
  return out;
}

// summary.md's BOP table (runs with BOP scores only).
std::string BopTable(const Summary& summary) {
  std::string out;
  bool any_bop = false, any_vsd = false;
  for (const ModelSummary& m : summary.models) {
    for (const GroupStats& g : m.groups) {
      any_bop = any_bop || g.bop.has_value();
      any_vsd = any_vsd || (g.bop && g.bop->ar_vsd);
    }
  }
  if (any_bop) {
    out +=
        "## BOP scores by region (AR over BOP's thresholds; ADD / ADD-S: fraction below 10 % of the diameter; a "
        "frame without an estimate is a miss)\n\n";
    out += any_vsd ? "| Region | Model | AR VSD | AR MSSD | AR MSPD | AR | AR (MSSD, MSPD) | ADD | ADD-S | Frames |\n"
                     "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|\n"
                   : "| Region | Model | AR MSSD | AR MSPD | AR (MSSD, MSPD) | ADD | ADD-S | Frames |\n"
                     "|---|---|---:|---:|---:|---:|---:|---:|\n";
    for (const std::string& group : std::vector<std::string>{"all", "A", "B", "C"}) {
      for (const ModelSummary& m : summary.models) {
        const GroupStats* g = FindGroup(m, group);
        if (g == nullptr || !g->bop || g->bop->targets == 0) continue;
        out += "|";
        AppendCell(out, group);
        AppendCell(out, DisplayName(m.model));
        const auto cell = [&out](const std::optional<double>& v) { AppendCell(out, v ? FormatFixed(*v, 3) : "-"); };
        if (any_vsd) cell(g->bop->ar_vsd);
        cell(g->bop->ar_mssd);
        cell(g->bop->ar_mspd);
        if (any_vsd) cell(g->bop->ar);
        for (double v : {g->bop->ar_mssd_mspd, g->bop->add_recall, g->bop->adds_recall}) cell(v);
        AppendCell(out, std::to_string(g->bop->targets));
        out += "\n";
      }
    }
    out += "\n";
  }
  return out;
}

}  // namespace

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
  out +=
      "## Every frame (mean absolute error of every frame with an estimate, measured or rejected)\n\n"
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
  out += TruthTable(summary, regions);
  out += FilterTable(summary, regions);
  out += BopTable(summary);
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
