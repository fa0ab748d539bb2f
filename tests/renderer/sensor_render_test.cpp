// The sensor model in the rendering jobs: a rig with a sensor block noises
// the colour images of frames and calibration pairs, never the depth and
// masks, gives the same bytes from the same inputs, and is recorded in the
// manifest; a rig without one records nothing.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "../test_support.h"
#include "aar/dataset.h"
#include "aar/file_io.h"
#include "aar/renderer/stereo_render_job.h"

namespace aar {
namespace {

using test::SourcePath;
using test::TempDir;

RenderJobOptions Options(const std::filesystem::path& output, const char* rig, const std::filesystem::path& path) {
  RenderJobOptions o;
  o.output = output;
  o.rig = SourcePath(rig);
  o.receiver_model = SourcePath("scenes/c12.glb");
  o.tanker_model = SourcePath("scenes/kc46.glb");
  o.board_model = SourcePath("scenes/calib_board.glb");
  o.far_boards_m = {};  // the twelve near boards
  o.flight_path = path;
  o.msaa = 1;
  o.depth = true;
  o.selection.end = 1;
  o.progress = false;
  return o;
}

TEST(SensorRender, NoisesColourNotTruthSameBytesAndRecordedInTheManifest) {
  TempDir dir("render-sensor");
  const std::filesystem::path csv = dir / "contact.csv";
  WriteFileAtomic(csv, "time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg\n0.0,-47.71,0.0,-18.9,0.0,0.0,0.0\n");
  for (const char* name : {"clean", "noisy-a", "noisy-b"}) {
    const char* rig = std::string(name) == "clean" ? "scenes/rig.json" : "scenes/rig-noisy.json";
    RenderFlightPathJob(Options(dir / name, rig, csv));
    RenderCalibrationJob(Options(dir / (std::string(name) + "-calib"), rig, csv));
  }
  // The same inputs give the same bytes, noise included.
  for (const char* kind : {"noisy-a", "noisy-a-calib"}) {
    const std::filesystem::path a = dir / kind;
    const std::filesystem::path b = dir / (std::string(kind).replace(6, 1, "b"));
    for (const auto& entry : std::filesystem::recursive_directory_iterator(a)) {
      if (!entry.is_regular_file()) continue;
      const auto relative = std::filesystem::relative(entry.path(), a);
      EXPECT_EQ(ReadFileBytes(entry.path()), ReadFileBytes(b / relative)) << relative;
    }
  }
  // Truth is untouched; the colour changes by noise around the clean image.
  for (const char* truth :
       {"frames/000000_left_depth.exr", "frames/000000_left_mask.png", "frames/000000_left_silhouette.png"}) {
    EXPECT_EQ(ReadFileBytes(dir / "clean" / truth), ReadFileBytes(dir / "noisy-a" / truth)) << truth;
  }
  for (const char* view : {"frames/000000_left.png", "frames/000000_right.png"}) {
    const cv::Mat clean = cv::imread((dir / "clean" / view).string(), cv::IMREAD_COLOR);
    const cv::Mat noisy = cv::imread((dir / "noisy-a" / view).string(), cv::IMREAD_COLOR);
    ASSERT_FALSE(clean.empty());
    cv::Mat difference;
    cv::subtract(noisy, clean, difference, cv::noArray(), CV_32F);
    cv::Scalar mean, deviation;
    cv::meanStdDev(difference.reshape(1), mean, deviation);
    std::printf("%s: noisy - clean %.3f +- %.3f codes\n", view, mean[0], deviation[0]);
    EXPECT_GT(deviation[0], 1.0) << view;       // noise of a few codes
    EXPECT_LT(deviation[0], 10.0) << view;      // not a different image
    EXPECT_LT(std::abs(mean[0]), 1.0) << view;  // no change of brightness
  }
  EXPECT_NE(ReadFileBytes(dir / "clean-calib/calib/000000_left.png"),
            ReadFileBytes(dir / "noisy-a-calib/calib/000000_left.png"));

  const auto manifest = [&](const char* name) {
    return nlohmann::json::parse(ReadFileBytes(dir / name / kManifestName)).at("image");
  };
  for (const char* name : {"noisy-a", "noisy-a-calib"}) {
    const nlohmann::json sensor = manifest(name).at("sensor");
    EXPECT_EQ(sensor.at("seed"), 1);
    EXPECT_EQ(sensor.at("exposure_e"), 2000.0);
    EXPECT_EQ(sensor.at("bayer"), "rggb");
    EXPECT_EQ(sensor.at("demosaicing"), "bilinear");
  }
  EXPECT_FALSE(manifest("clean").contains("sensor"));
  EXPECT_FALSE(manifest("clean-calib").contains("sensor"));
  EXPECT_TRUE(ReadSidecar(SidecarPath(dir / "noisy-a", "frame", 0)).rig.sensor.has_value());
}

}  // namespace
}  // namespace aar
