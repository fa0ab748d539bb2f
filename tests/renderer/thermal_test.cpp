// The thermal camera (thermal_scene.h, thermal_sensor.h; docs/rendering.md,
// "Thermal camera"): the standard atmosphere and the recovery temperature,
// the surfaces' radiance, the detector's noise against its NETD, and a
// rendered radiometric pair of scenes/rig-lwir.json whose sky, skin and
// nacelles read the brightness temperatures the model gives.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "../test_support.h"
#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/json_file.h"
#include "aar/renderer/stereo_render_job.h"
#include "aar/renderer/thermal_scene.h"
#include "aar/renderer/thermal_sensor.h"
#include "aar/rig.h"

namespace aar {
namespace {

using test::SourcePath;
using test::TempDir;

TEST(ThermalScene, TheAirAndTheSkinAreTheStandardAtmospheresAndTheRecoveryTemperature) {
  EXPECT_NEAR(StandardAtmosphereTemperatureK(0.0), 288.15, 1e-12);
  EXPECT_NEAR(StandardAtmosphereTemperatureK(7000.0), 242.65, 1e-9);  // ISO 2533: 242.65 K at 7 km
  EXPECT_NEAR(StandardAtmosphereTemperatureK(15000.0), 216.65, 1e-12);
  // 120 m/s: 0.89 x 120^2 / (2 x 1004.5) = 6.379 K above the air.
  EXPECT_NEAR(RecoveryTemperatureK(242.65, 120.0) - 242.65, 6.3793, 1e-4);
  Primitive paint, metal;
  paint.metallic = 0.0f;
  metal.metallic = 1.0f;
  EXPECT_NEAR(EmissivityOf(paint), 0.9, 1e-12);
  EXPECT_NEAR(EmissivityOf(metal), 0.1, 1e-7);
  EXPECT_THROW(StandardAtmosphereTemperatureK(30000.0), Error);
}

// A uniform image of a 250 K scene through a 50 mK camera: its mean reads
// 250 K, its spread is NETD x dL/dT(300 K) / dL/dT(250 K), the fixed
// pattern repeats from frame to frame and the temporal noise does not.
TEST(ThermalSensor, TheNoiseIsTheNetdAsARadianceAndThePatternIsTheCameras) {
  ThermalCamera camera;
  camera.netd_mk = 50.0;
  camera.nonuniformity_mk = 30.0;
  const auto scene = std::make_shared<const ThermalScene>(camera, ThermalSceneOptions{}, 7000.0);
  const ThermalSensor sensor(scene);
  const float l = static_cast<float>(scene->table.Radiance(250.0) / scene->reference_radiance);
  const LinearImage flat{256, 256, std::vector<float>(256 * 256 * 3, l)};
  const LinearImage a = sensor.Apply(flat, SensorExposure{0, 1, 0}), b = sensor.Apply(flat, SensorExposure{0, 2, 0});
  double mean = 0.0, sq = 0.0, cross = 0.0;
  const size_t n = 256 * 256;
  for (size_t p = 0; p < n; ++p) mean += a.rgb[3 * p];
  mean /= n;
  for (size_t p = 0; p < n; ++p) {
    sq += (a.rgb[3 * p] - mean) * (a.rgb[3 * p] - mean);
    cross += (a.rgb[3 * p] - mean) * (b.rgb[3 * p] - mean);
  }
  const double sigma = std::sqrt(sq / (n - 1));
  const double gain = scene->table.Slope(300.0) / scene->table.Slope(250.0);
  const double expected = std::hypot(0.050, 0.030) * gain;
  EXPECT_NEAR(mean, 250.0, 4.0 * expected / std::sqrt(static_cast<double>(n)) + 2e-4);
  EXPECT_NEAR(sigma / expected, 1.0, 0.02);
  // Between two frames only the fixed pattern is shared: correlation 30^2 / (30^2 + 50^2).
  EXPECT_NEAR(cross / sq, 900.0 / 3400.0, 0.02);
  EXPECT_EQ(a.rgb[0], a.rgb[1]);  // every channel the brightness temperature
  EXPECT_EQ(a.rgb[0], a.rgb[2]);
}

// Rendered (frame 600, x4, with depth): the sky reads its 220 K, the skin
// 0.9 B(249.03 K) + 0.1 B(220 K) as a brightness temperature, the nacelles
// 40 K warmer than the skin; both images are one-channel 16-bit PNGs, and
// the manifest says so; the visible camera's light is refused.
TEST(ThermalRender, ARadiometricPairReadsTheModelsTemperatures) {
  TempDir dir("thermal");
  RenderJobOptions o;
  o.output = dir / "lwir";
  o.rig = SourcePath("scenes/rig-lwir.json");
  o.receiver_model = SourcePath("scenes/c12.glb");
  o.tanker_model = SourcePath("scenes/kc46.glb");
  o.flight_path = SourcePath("flightpaths/conops.csv");
  o.progress = false;
  o.msaa = 4;
  o.depth = true;
  o.selection.begin = 600;
  o.selection.end = 601;
  RenderFlightPathJob(o);
  const FrameSidecar s = ReadSidecar(SidecarPath(o.output, "frame", 600));
  const cv::Mat left = cv::imread((o.output / s.files.at("left").path).string(), cv::IMREAD_UNCHANGED);
  const cv::Mat right = cv::imread((o.output / s.files.at("right").path).string(), cv::IMREAD_UNCHANGED);
  const cv::Mat ids = cv::imread((o.output / s.files.at("left_mask").path).string(), cv::IMREAD_GRAYSCALE);
  ASSERT_EQ(left.type(), CV_16UC1);
  ASSERT_EQ(right.type(), CV_16UC1);
  // Pixels well inside each class (no edge shares them).
  const auto inside = [&](int id) {
    cv::Mat m = ids == id, eroded;
    cv::erode(m, eroded, cv::Mat::ones(5, 5, CV_8U));
    std::vector<double> kelvin;
    for (int y = 0; y < left.rows; ++y) {
      for (int x = 0; x < left.cols; ++x) {
        if (eroded.at<uint8_t>(y, x)) kelvin.push_back(left.at<uint16_t>(y, x) / 100.0);
      }
    }
    std::sort(kelvin.begin(), kelvin.end());
    return kelvin;
  };
  const std::vector<double> sky = inside(0), receiver = inside(1);
  ASSERT_GT(sky.size(), 10000u);
  ASSERT_GT(receiver.size(), 2000u);
  const ThermalScene scene(*LoadRig(o.rig).lwir, ThermalSceneOptions{}, 7000.0);
  const double skin =
      scene.table.BrightnessTemperature(scene.SurfaceRadiance(scene.skin_k, 0.9) * scene.reference_radiance);
  const double nacelle =
      scene.table.BrightnessTemperature(scene.SurfaceRadiance(scene.nacelle_k, 0.9) * scene.reference_radiance);
  double sky_mean = 0.0;
  for (double k : sky) sky_mean += k;
  sky_mean /= static_cast<double>(sky.size());
  EXPECT_NEAR(sky_mean, 220.0, 0.01);
  EXPECT_NEAR(receiver[receiver.size() / 2], skin, 0.1);  // the median: the painted skin
  const size_t hot = static_cast<size_t>(
      std::count_if(receiver.begin(), receiver.end(), [&](double k) { return std::abs(k - nacelle) < 0.5; }));
  EXPECT_GT(hot, 100u);  // the nacelles
  EXPECT_GT(nacelle - skin, 30.0);
  const nlohmann::json manifest = ReadJsonFile(o.output / "manifest.json");
  EXPECT_EQ(manifest.at("image").at("lwir").at("netd_mk"), 50.0);
  EXPECT_NEAR(manifest.at("frames").at("thermal").at("skin_temperature_k").get<double>(), scene.skin_k, 1e-9);

  // The visible camera's light and the other backgrounds are refused with it.
  o.output = dir / "terrain";
  o.background.kind = BackgroundKind::kTerrain;
  EXPECT_NE(test::ErrorOf([&] { RenderFlightPathJob(o); }).find("renders over the flat sky only"), std::string::npos);
  o.background.kind = BackgroundKind::kFlat;
  o.shading = Shading::kPbr;
  EXPECT_NE(test::ErrorOf([&] { RenderFlightPathJob(o); }).find("the thermal scene is emission"), std::string::npos);
  o.shading = Shading::kMatte;
}

// The heated board (320 K): its light squares (luminance 0.9: e 0.865)
// and dark ones (0.02: e 0.117) read e B(320 K) + (1 - e) B(220 K) as
// brightness temperatures; the manifest records the board's temperature.
TEST(ThermalRender, TheHeatedBoardShowsItsEmissivityPattern) {
  TempDir dir("thermal-board");
  RenderJobOptions o;
  o.output = dir / "calib";
  o.rig = SourcePath("scenes/rig-lwir.json");
  o.board_model = SourcePath("scenes/calib_board.glb");
  o.progress = false;
  o.msaa = 4;
  o.selection.begin = 0;
  o.selection.end = 1;
  RenderCalibrationJob(o);
  const FrameSidecar s = ReadSidecar(SidecarPath(o.output, "calib", 0));
  const cv::Mat left = cv::imread((o.output / s.files.at("left").path).string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(left.type(), CV_16UC1);
  const ThermalScene scene(*LoadRig(o.rig).lwir, ThermalSceneOptions{}, 7000.0);
  const auto reads = [&](double emissivity) {
    return scene.table.BrightnessTemperature(scene.SurfaceRadiance(320.0, emissivity) * scene.reference_radiance);
  };
  const double light = reads(0.1 + 0.85 * 0.9), dark = reads(0.1 + 0.85 * 0.02);
  int at_light = 0, at_dark = 0;
  for (int y = 0; y < left.rows; ++y) {
    for (int x = 0; x < left.cols; ++x) {
      const double k = left.at<uint16_t>(y, x) / 100.0;
      at_light += std::abs(k - light) < 0.5 ? 1 : 0;
      at_dark += std::abs(k - dark) < 0.5 ? 1 : 0;
    }
  }
  EXPECT_GT(light - dark, 40.0);
  EXPECT_GT(at_light, 20000);  // about a third of the image each
  EXPECT_GT(at_dark, 20000);
  const nlohmann::json manifest = ReadJsonFile(o.output / "manifest.json");
  EXPECT_EQ(manifest.at("calib").at("thermal").at("board_temperature_k"), 320.0);
}

}  // namespace
}  // namespace aar
