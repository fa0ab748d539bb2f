// End to end with lens distortion (scenes/rig-distorted.json): the x16
// calibration boards (36 at three distances, plus the 8 towards the image
// corners and edges) rendered through the lens, calibrated by aar-analyze
// (which estimates the distortion because the rig declares it), recover the
// true coefficients; the pinhole rig's calibration keeps them at zero.

#include "aar/lens.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "aar/analyzer/analysis_run.h"
#include "aar/dataset.h"
#include "aar/file_io.h"
#include "aar/rig.h"
#include "pipeline_support.h"

namespace aar {
namespace {

namespace fs = std::filesystem;
using test::Quote;
using test::RunAnalyze;
using test::TempDir;

// Tolerances (docs/analysis.md, "Calibration"): the coefficients of each
// camera, and the largest error of a pixel's ray over the whole image.
// Measured (lavapipe, x16, 44 pairs): k1 0.0021 / 0.0017, k2 0.0065 / 0.0051,
// p1, p2 at most 1.9e-5, rays 0.93 / 0.71 px at worst (the outermost 60-70 px
// of the image hold no corners); the tolerances are about twice that.
constexpr double kK1Tolerance = 0.005;
constexpr double kK2Tolerance = 0.015;
constexpr double kTangentialTolerance = 5e-5;
constexpr double kRayErrorTolerancePx = 2.0;

TEST(LensPipeline, CalibrationRecoversTheDistortionCoefficients) {
  TempDir dir("lens-calibrate");
  const fs::path dataset = dir / "lens";
  const std::string rig = test::SourcePath("scenes/rig-distorted.json").string();
  const test::CommandResult render =
      test::RunCommand(Quote(test::RenderExe()) + " calib " + Quote(dataset) + " --rig " + Quote(rig) +
                       " --msaa 16 --far-boards 30,45 --corner-boards --no-progress");
  ASSERT_EQ(render.exit_code, 0) << render.output;
  const fs::path out = dir / "calibration";
  const test::CommandResult r = RunAnalyze("calibrate " + Quote(dataset) + " --out " + Quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::printf("%s", r.output.c_str());

  const nlohmann::json report = ReadJsonFile(out / kCalibrationReportName);
  ASSERT_TRUE(report.contains("distortion")) << report.dump(2);
  EXPECT_EQ(report.at("distortion").at("model"), "brown-conrady");
  const StereoRig truth = LoadRig(rig);
  for (const auto& [key, lens] :
       {std::pair{"D1", truth.left.intrinsics.distortion}, std::pair{"D2", truth.right.intrinsics.distortion}}) {
    const nlohmann::json& d = report.at("distortion").at(key).at(0);  // one row: k1 k2 p1 p2 k3
    EXPECT_NEAR(d.at(0).get<double>(), lens.k1, kK1Tolerance) << key;
    EXPECT_NEAR(d.at(1).get<double>(), lens.k2, kK2Tolerance) << key;
    EXPECT_NEAR(d.at(2).get<double>(), lens.p1, kTangentialTolerance) << key;
    EXPECT_NEAR(d.at(3).get<double>(), lens.p2, kTangentialTolerance) << key;
    EXPECT_EQ(d.at(4).get<double>(), 0.0) << key;  // k3 fixed
  }
  const nlohmann::json& versus = report.at("versus_ideal");
  EXPECT_LT(versus.at("left_ray_error_max_px").get<double>(), kRayErrorTolerancePx);
  EXPECT_LT(versus.at("right_ray_error_max_px").get<double>(), kRayErrorTolerancePx);
  EXPECT_LT(std::abs(versus.at("baseline_error_percent").get<double>()), 0.05);
  EXPECT_LT(std::abs(versus.at("focal_error_percent").get<double>()), 0.05);
}

TEST(LensPipeline, PinholeRigKeepsTheDistortionAtZero) {
  ASSERT_DATASETS();
  TempDir dir("lens-pinhole-calibrate");
  const fs::path out = dir / "calibration";
  const test::CommandResult r =
      RunAnalyze("calibrate " + Quote(test::SharedDatasets().near_contact) + " --out " + Quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json report = ReadJsonFile(out / kCalibrationReportName);
  EXPECT_FALSE(report.contains("distortion"));
  const std::string yaml = ReadFileBytes(out / kCalibrationYamlName);
  EXPECT_NE(yaml.find("D1: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n   data: [ 0., 0., 0., 0., 0. ]"),
            std::string::npos)
      << yaml;
}

}  // namespace
}  // namespace aar
