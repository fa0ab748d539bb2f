// End to end with the thermal pair (scenes/rig-lwir.json): the heated
// boards rendered in the infrared and calibrated by aar-analyze from their
// radiometric images recover the rig's focal length and baseline, two
// region C frames analyzed with that calibration are measured, and their
// views export to a ROS bag as mono16.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "aar/analyzer/run_files.h"
#include "aar/json_file.h"
#include "pipeline_support.h"

namespace aar {
namespace {

namespace fs = std::filesystem;
using test::Quote;
using test::RunAnalyze;
using test::TempDir;

// The boards at 15 and 30 m (`--far-boards 30`: at 45 m a square is about
// 7 px at 640 x 512, too small for OpenCV's detector). Measured (lavapipe, x4): 17 of the 24 pairs found,
// RMS 0.10 px, focal -0.029 %, baseline +0.104 %; the bounds are several
// times that.
TEST(ThermalPipeline, TheHeatedBoardsCalibrateTheThermalPair) {
  TempDir dir("thermal-pipeline");
  const fs::path dataset = dir / "lwir";
  const std::string rig = test::SourcePath("scenes/rig-lwir.json").string();
  const test::CommandResult boards =
      test::RunCommand(Quote(test::RenderExe()) + " calib " + Quote(dataset) + " --rig " + Quote(rig) +
                       " --msaa 4 --far-boards 30 --no-progress");
  ASSERT_EQ(boards.exit_code, 0) << boards.output;
  const fs::path out = dir / "calibration";
  const test::CommandResult r = RunAnalyze("calibrate " + Quote(dataset) + " --out " + Quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json report = ReadJsonFile(out / kCalibrationReportName);
  const nlohmann::json& versus = report.at("versus_ideal");
  std::printf("pairs %d, RMS %.3f px, focal %+.4f %%, baseline %+.4f %%\n", report.at("used_pairs").get<int>(),
              report.at("rms_reprojection_px").get<double>(), versus.at("focal_error_percent").get<double>(),
              versus.at("baseline_error_percent").get<double>());
  EXPECT_GE(report.at("used_pairs").get<int>(), 12);
  EXPECT_LT(report.at("rms_reprojection_px").get<double>(), 0.3);
  EXPECT_LT(std::abs(versus.at("focal_error_percent").get<double>()), 0.5);
  EXPECT_LT(std::abs(versus.at("baseline_error_percent").get<double>()), 0.5);

  const test::CommandResult frames =
      test::RunCommand(Quote(test::RenderExe()) + " render " + Quote(dataset) + " --rig " + Quote(rig) +
                       " --msaa 4 --frames 590:592 --no-progress");
  ASSERT_EQ(frames.exit_code, 0) << frames.output;
  const fs::path run = dir / "run";
  const test::CommandResult analyzed =
      RunAnalyze("run " + Quote(dataset) + " --calibration " + Quote(out / "calibration.yaml") +
                 " --frames 590:592 --out " + Quote(run));
  ASSERT_EQ(analyzed.exit_code, 0) << analyzed.output;
  EXPECT_NE(analyzed.output.find("2 frames analyzed, 0 not measured"), std::string::npos) << analyzed.output;

  // The views in a ROS bag as mono16, read back by Debian's python3-rosbag.
  const test::CommandResult exported =
      RunAnalyze("export " + Quote(dataset) + " --format rosbag --frames 590:592 --out " + Quote(dir / "bag"));
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  const test::CommandResult check =
      test::RunCommand("/usr/bin/python3 " + Quote(test::SourcePath("tests/pipeline/check_rosbag.py")) + " " +
                       Quote(dir / "bag/dataset.bag") + " " + Quote(dataset) + " 590 2");
  EXPECT_EQ(check.exit_code, 0) << check.output;
}

}  // namespace
}  // namespace aar
