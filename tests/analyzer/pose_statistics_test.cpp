// Per-frame records, the results CSV, shard merging and the thesis's
// statistics (mean absolute error, RMS error eq. 4, ICP time mean and std).

#include "aar/analyzer/pose_statistics.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/text.h"

namespace aar {
namespace {

namespace fs = std::filesystem;

Pose MakePose(double x, double y, double z, double roll, double pitch, double yaw) {
  Pose p;
  p.translation_m = Eigen::Vector3d(x, y, z);
  p.roll_deg = roll;
  p.pitch_deg = pitch;
  p.yaw_deg = yaw;
  return p;
}

// An ok frame at `range_m` whose estimate is the truth plus `error`.
FrameResult OkFrame(size_t index, double range_m, const SixDof& error, double icp_ms = 100.0) {
  FrameResult f;
  f.frame = index;
  f.time_s = 0.1 * static_cast<double>(index);
  f.range_m = range_m;
  f.region = "C";
  f.truth = MakePose(-range_m, 0.0, -18.0, 0.0, 0.0, 0.0);
  f.estimate = MakePose(-range_m + error[0], error[1], -18.0 + error[2], error[3], error[4], error[5]);
  f.error = PoseError(f.estimate, f.truth);
  f.sensed_points = 9000 + index;
  f.icp_iterations = 30;
  f.icp_converged = false;
  f.icp_rmse_m = 0.05;
  f.icp_inliers = 7000;
  f.times.icp_ms = icp_ms;
  f.times.total_ms = icp_ms + 50.0;
  return f;
}

SixDof Dof(double x, double y, double z, double roll, double pitch, double yaw) {
  SixDof v;
  v.values = {x, y, z, roll, pitch, yaw};
  return v;
}

const GroupStats& Group(const ModelSummary& m, const std::string& name) {
  for (const GroupStats& g : m.groups) {
    if (g.group == name) return g;
  }
  throw std::runtime_error("no group " + name);
}

TEST(PoseStatistics, ErrorIsEstimateMinusTruthWithWrappedAngles) {
  const SixDof e =
      PoseError(MakePose(1.5, -2.0, 3.0, 179.0, 10.0, -179.0), MakePose(1.0, -1.0, 3.5, -179.0, 12.0, 179.0));
  EXPECT_DOUBLE_EQ(e[0], 0.5);
  EXPECT_DOUBLE_EQ(e[1], -1.0);
  EXPECT_DOUBLE_EQ(e[2], -0.5);
  EXPECT_DOUBLE_EQ(e[3], -2.0);  // 179 - (-179) = 358 -> -2
  EXPECT_DOUBLE_EQ(e[4], -2.0);
  EXPECT_DOUBLE_EQ(e[5], 2.0);  // -179 - 179 = -358 -> 2
  EXPECT_DOUBLE_EQ(PoseError(MakePose(0, 0, 0, 90, 0, 0), MakePose(0, 0, 0, -90, 0, 0))[3], 180.0);  // (-180, 180]
  EXPECT_DOUBLE_EQ(PoseError(MakePose(0, 0, 0, -90, 0, 0), MakePose(0, 0, 0, 90, 0, 0))[3], 180.0);
}

TEST(PoseStatistics, MeanAbsoluteAndRmsErrorByHand) {
  std::vector<FrameResult> frames = {
      OkFrame(0, 35.0, Dof(0.1, 0.0, 0.0, 1.0, 0.0, 0.0)),
      OkFrame(1, 35.0, Dof(-0.2, 0.0, 0.0, -2.0, 0.0, 0.0)),
      OkFrame(2, 35.0, Dof(0.3, 0.0, 0.0, 2.0, 0.0, 0.0)),
  };
  FrameResult failed = OkFrame(3, 35.0, Dof(5.0, 5.0, 5.0, 5.0, 5.0, 5.0));
  failed.status = "too few sensed points";
  frames.push_back(failed);
  const GroupStats c = Group(SummarizeFrames("shelled", frames), "C");
  EXPECT_EQ(c.frames, 4u);
  EXPECT_EQ(c.ok, 3u);
  EXPECT_EQ(c.failed, 1u);
  EXPECT_NEAR(c.mean_abs_error[0], 0.2, 1e-12);                               // (0.1 + 0.2 + 0.3) / 3
  EXPECT_NEAR(c.rms_error[0], std::sqrt((0.01 + 0.04 + 0.09) / 3.0), 1e-12);  // thesis eq. 4
  EXPECT_NEAR(c.mean_abs_error[3], 5.0 / 3.0, 1e-12);
  EXPECT_NEAR(c.rms_error[3], std::sqrt(9.0 / 3.0), 1e-12);
  EXPECT_EQ(c.mean_abs_error[1], 0.0);
}

TEST(PoseStatistics, GroupsByRegionAndRangeBin) {
  const SixDof zero;
  const std::vector<FrameResult> frames = {OkFrame(0, 35.0, zero),  OkFrame(1, 50.0, zero), OkFrame(2, 100.0, zero),
                                           OkFrame(3, 200.0, zero), OkFrame(4, 60.0, zero), OkFrame(5, 20.0, zero)};
  const ModelSummary m = SummarizeFrames("full", frames);
  std::vector<std::string> names;
  for (const GroupStats& g : m.groups) names.push_back(g.group);
  EXPECT_EQ(names, (std::vector<std::string>{"all", "A", "B", "C", "20-60", "60-110"}));
  EXPECT_EQ(Group(m, "all").frames, 6u);
  EXPECT_EQ(Group(m, "A").frames, 1u);       // 100
  EXPECT_EQ(Group(m, "B").frames, 2u);       // 50, 60
  EXPECT_EQ(Group(m, "C").frames, 1u);       // 35
  EXPECT_EQ(Group(m, "20-60").frames, 3u);   // 35, 50, 20
  EXPECT_EQ(Group(m, "60-110").frames, 2u);  // 100, 60
}

TEST(PoseStatistics, IcpTimeMeanAndSampleStandardDeviation) {
  const SixDof zero;
  const std::vector<FrameResult> frames = {OkFrame(0, 35.0, zero, 10.0), OkFrame(1, 36.0, zero, 20.0),
                                           OkFrame(2, 37.0, zero, 30.0)};
  const GroupStats c = Group(SummarizeFrames("shelled", frames), "C");
  EXPECT_DOUBLE_EQ(c.icp_ms_mean, 20.0);
  EXPECT_DOUBLE_EQ(c.icp_ms_std, 10.0);  // sqrt((100 + 0 + 100) / 2)
}

TEST(PoseStatistics, CsvRoundTripsAndPutsTimingLast) {
  FrameResult failed = OkFrame(7, 120.0, SixDof{});
  failed.status = "no points, tail out of view\nreally";
  failed.region = "A";
  const std::vector<FrameResult> frames = {OkFrame(3, 35.5, Dof(0.01, -0.02, 0.03, 0.4, -0.5, 0.6)), failed};
  const std::string text = FormatFrameResults(frames);
  const std::vector<FrameResult> read = ParseFrameResults(text, "results.csv");
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(FormatFrameResults(read), text);
  EXPECT_EQ(read[1].status, "no points; tail out of view really");
  EXPECT_FALSE(read[1].ok());
  EXPECT_NEAR(read[0].error[5], 0.6, 1e-6);
  EXPECT_EQ(read[0].sensed_points, 9003u);

  const std::vector<std::string> columns = SplitCsvLine(FrameResultsCsvHeader());
  ASSERT_EQ(columns.size(), 59u);
  EXPECT_EQ(columns[0], "frame");
  EXPECT_EQ(columns[27], "icp_inliers");
  EXPECT_EQ(columns[33], "truth_error_by_fraction");
  EXPECT_EQ(columns[34], "filt_est_x_m");
  EXPECT_EQ(columns[45], "filt_err_yaw_deg");
  EXPECT_EQ(columns[46], "mssd_m");
  EXPECT_EQ(columns[49], "adds_m");
  EXPECT_EQ(columns[50], "vsd_errors");
  EXPECT_EQ(columns[51], "truth_on_propellers");
  EXPECT_EQ(columns[52], "truth_propellers_kept");  // `cut -d, -f1-53` keeps everything but timing
  for (size_t i = 53; i < columns.size(); ++i) EXPECT_EQ(columns[i].rfind("ms_", 0), 0u) << columns[i];
  // A failed frame's estimate and error are empty fields.
  const std::string failed_line = text.substr(text.find("\n7,") + 1);
  EXPECT_NE(failed_line.find(",,,,,,,,,,,,"), std::string::npos) << failed_line;
}

TEST(PoseStatistics, CsvReaderReportsFileLineAndReason) {
  const std::string header = FrameResultsCsvHeader() + "\n";
  const auto expect_error = [](const std::string& text, const std::string& reason) {
    try {
      ParseFrameResults(text, "shard0.csv");
      ADD_FAILURE() << "no exception";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
    }
  };
  expect_error("", "empty file");
  expect_error("frame,time\n", "shard0.csv:1: not a frame-results CSV");
  expect_error(header + "1,2,3\n", "shard0.csv:2: expected 59 columns, found 3");
  std::string line = FormatFrameResults({OkFrame(1, 35.0, SixDof{})});
  line = line.substr(line.find('\n') + 1);
  std::string bad = line;
  bad.replace(bad.find(",C,"), 3, ",D,");
  expect_error(header + bad, "region 'D'");
  bad = line;
  bad.replace(0, 1, "x");
  expect_error(header + line + bad, "shard0.csv:3 column 1");
}

TEST(PoseStatistics, WriteAndReadFile) {
  const fs::path dir = fs::temp_directory_path() / ("aar_pose_statistics_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::vector<FrameResult> frames = {OkFrame(1, 40.0, Dof(0.1, 0.2, 0.3, 1, 2, 3))};
  WriteFrameResults(dir / "results.csv", frames);
  EXPECT_EQ(FormatFrameResults(ReadFrameResults(dir / "results.csv")), FormatFrameResults(frames));
  EXPECT_THROW(ReadFrameResults(dir / "missing.csv"), Error);
  fs::remove_all(dir);
}

TEST(PoseStatistics, MergeSortsByFrameAndRejectsDuplicates) {
  const SixDof zero;
  const std::vector<std::vector<FrameResult>> shards = {{OkFrame(0, 35, zero), OkFrame(2, 35, zero)},
                                                        {OkFrame(1, 35, zero), OkFrame(3, 35, zero)}};
  const std::vector<FrameResult> merged = MergeFrameResults(shards);
  ASSERT_EQ(merged.size(), 4u);
  for (size_t i = 0; i < merged.size(); ++i) EXPECT_EQ(merged[i].frame, i);
  try {
    MergeFrameResults({{OkFrame(0, 35, zero), OkFrame(5, 35, zero)}, {OkFrame(5, 35, zero)}}, {"a.csv", "b.csv"});
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("frame 5 appears in both a.csv and b.csv"), std::string::npos) << e.what();
  }
  EXPECT_THROW(MergeFrameResults({{OkFrame(4, 35, zero), OkFrame(4, 35, zero)}}), Error);
}

TEST(PoseStatistics, ShardedSummaryEqualsSingleRun) {
  std::vector<FrameResult> all;
  for (size_t i = 0; i < 40; ++i) {
    const double s = std::sin(static_cast<double>(i));
    all.push_back(OkFrame(i, 30.0 + 2.0 * static_cast<double>(i),
                          Dof(0.0123456789 * s, 0.01 / (1 + i), -0.03 * s, 0.333333333 * s, 0.7, -0.1 * s),
                          90.0 + static_cast<double>(i)));
  }
  std::vector<std::vector<FrameResult>> shards(3);
  for (size_t i = 0; i < all.size(); ++i) shards[i % 3].push_back(all[i]);
  std::vector<std::vector<FrameResult>> read_back;
  for (const auto& shard : shards) read_back.push_back(ParseFrameResults(FormatFrameResults(shard), "shard"));
  const Summary single{{SummarizeFrames("shelled", all)}};
  const Summary merged{{SummarizeFrames("shelled", MergeFrameResults(read_back))}};
  EXPECT_EQ(SummaryToJson(single).dump(), SummaryToJson(merged).dump());
}

// A shard's filter sees only its own frames; the merge filters the merged frames again and then equals, byte for
// byte, the single run (the filter works on the values as the CSV stores them).
TEST(PoseStatistics, MergedFilterEqualsSingleRun) {
  const PoseFilterOptions filter{.window_s = 0.35};  // OkFrame's frames are 0.1 s apart: 4 frames a window
  std::vector<FrameResult> all;
  for (size_t i = 0; i < 30; ++i) {
    const double s = std::sin(0.7 * static_cast<double>(i));
    all.push_back(OkFrame(i, 33.0 + 0.0123456789 * static_cast<double>(i),
                          Dof(0.0123456789 * s, 0.01 / (1 + i), -0.03 * s, 0.333333333 * s, 0.7, -0.1 * s)));
  }
  all[11].status = "too few sensed points";
  std::vector<std::vector<FrameResult>> read_back(3);
  for (size_t shard = 0; shard < 3; ++shard) {
    std::vector<FrameResult> frames;
    for (size_t i = shard; i < all.size(); i += 3) frames.push_back(all[i]);
    FilterFrameResults(frames, filter);
    read_back[shard] = ParseFrameResults(FormatFrameResults(frames), "shard");
  }
  FilterFrameResults(all, filter);
  std::vector<FrameResult> merged = MergeFrameResults(read_back);
  EXPECT_NE(FormatFrameResults(merged), FormatFrameResults(all));  // the shards' own filters
  FilterFrameResults(merged, filter);
  EXPECT_EQ(FormatFrameResults(merged), FormatFrameResults(all));
  EXPECT_FALSE(all[11].filtered);
  ASSERT_TRUE(all[12].filtered);  // right after a failed frame: its own estimate
  EXPECT_NEAR(all[12].filtered_error[3], all[12].error[3], 1e-6);
  ASSERT_TRUE(all[20].filtered);  // four frames in the window: smoothed
  EXPECT_GT(std::abs(all[20].filtered_error[3] - all[20].error[3]), 0.01);
}

TEST(PoseStatistics, JitterIsTheRmsChangeOfTheErrorBetweenOkNeighbours) {
  std::vector<FrameResult> frames;
  for (const double x : {0.0, 0.1, 0.3, 0.0, 0.5, 0.2}) {
    frames.push_back(OkFrame(frames.size(), 35.0, Dof(x, 0, 0, 0, 0, 0)));
  }
  frames[4].status = "too few sensed points";                      // neither 3 -> 4 nor 4 -> 5 is a pair
  FilterFrameResults(frames, PoseFilterOptions{.window_s = 0.0});  // filtered = per frame
  const GroupStats& c = Group(SummarizeFrames("shelled", frames), "C");
  EXPECT_EQ(c.jitter_pairs, 3u);
  EXPECT_NEAR(c.jitter_rms[0], std::sqrt((0.01 + 0.04 + 0.09) / 3.0), 1e-9);
  EXPECT_NEAR(c.filtered_jitter_rms[0], c.jitter_rms[0], 1e-9);
  EXPECT_NEAR(c.filtered_mean_abs_error[0], c.mean_abs_error[0], 1e-9);
  EXPECT_EQ(c.jitter_rms[1], 0.0);
}

TEST(PoseStatistics, SummaryJsonKeepsTimingApart) {
  const SixDof e = Dof(0.1, 0.1, 0.1, 1, 1, 1);
  std::vector<FrameResult> fast = {OkFrame(0, 35, e, 10.0), OkFrame(1, 80, e, 12.0)};
  std::vector<FrameResult> slow = fast;
  for (FrameResult& f : slow) f.times.icp_ms *= 7.0;
  const nlohmann::json a = SummaryToJson(Summary{{SummarizeFrames("shelled", fast)}});
  const nlohmann::json b = SummaryToJson(Summary{{SummarizeFrames("shelled", slow)}});
  EXPECT_EQ(a["schema"], "aar-summary/1");
  EXPECT_EQ(a["models"], b["models"]);
  EXPECT_NE(a["timing"], b["timing"]);
  EXPECT_DOUBLE_EQ(a["timing"]["shelled"]["C"]["icp_ms_mean"].get<double>(), 10.0);
  EXPECT_DOUBLE_EQ(a["models"]["shelled"]["C"]["mean_abs_error"]["x_m"].get<double>(), 0.1);
  EXPECT_TRUE(a["models"]["shelled"]["B"]["rms_error"].is_null());  // no frame in B
  EXPECT_EQ(a["models"]["shelled"]["all"]["ok"], 2);
}

TEST(PoseStatistics, MarkdownFollowsThesisTables) {
  // Full-model and shelled-model errors of thesis Table 1 (20-60 m, X): 0.205 vs 0.142.
  const Summary summary{{SummarizeFrames("full", {OkFrame(0, 40, Dof(0.205, 0.106, 0.281, 0.539, 1.692, 1.075))}),
                         SummarizeFrames("shelled", {OkFrame(0, 40, Dof(0.142, 0.0458, 0.104, 0.381, 0.641, 0.529))})}};
  const std::string md = SummaryToMarkdown(summary);
  EXPECT_NE(md.find("| Range | Model | X (m) | Y (m) | Z (m) | Roll (deg) | Pitch (deg) | Yaw (deg) |"),
            std::string::npos);
  EXPECT_NE(md.find("| 20-60 m | Full Model | 0.205 | 0.106 | 0.281 | 0.539 | 1.692 | 1.075 | 1/1 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| | Shelled Model | 0.142 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| | Difference (%) | 30.73 |"), std::string::npos) << md;  // (0.205 - 0.142) / 0.205
  EXPECT_NE(md.find("| Region | Model |"), std::string::npos);
  EXPECT_NE(md.find("Average ICP time (ms)"), std::string::npos);
  EXPECT_NE(md.find("| 60-110 m | Full Model | n/a |"), std::string::npos) << md;
}

}  // namespace
}  // namespace aar
