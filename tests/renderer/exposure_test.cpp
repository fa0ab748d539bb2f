// Motion blur and propellers (issue 9, items 4 and 5): the exposure's
// instants, RenderExposure against RenderColor, and the render job with
// --propellers and --shutter-ms against the same frames without them.

#include "aar/renderer/exposure.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <functional>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "../test_support.h"
#include "aar/dataset.h"
#include "aar/file_io.h"
#include "aar/pose.h"
#include "aar/renderer/msaa.h"
#include "aar/renderer/scene_model.h"
#include "aar/renderer/scene_renderer.h"
#include "aar/renderer/stereo_render_job.h"
#include "aar/renderer/vulkan_context.h"
#include "aar/rig.h"

namespace aar {
namespace {

using test::ErrorOf;
using test::SourcePath;
using test::TempDir;

TEST(Exposure, InstantsAreTheMidpointsOfEqualSlicesAboutTheSample) {
  EXPECT_EQ(ExposureOffsets(0.0, 16), std::vector<double>{0.0});
  const std::vector<double> four = ExposureOffsets(4.0, 4);
  ASSERT_EQ(four.size(), 4u);
  const double expected[4] = {-1.5e-3, -0.5e-3, 0.5e-3, 1.5e-3};
  for (size_t k = 0; k < 4; ++k) EXPECT_NEAR(four[k], expected[k], 1e-15);
}

// The same scene at every instant is the still image: exactly at x1 (four
// equal passes averaged), and an instant count that does not divide the
// MSAA passes is refused.
TEST(Exposure, StillSceneOverAnExposureIsTheStillImage) {
  VulkanContext context{VulkanContextOptions{}};
  const StereoRig rig = LoadRig(SourcePath("scenes/rig.json"));
  SceneRenderer renderer(context, rig.left.intrinsics.width_px, rig.left.intrinsics.height_px);
  Pose contact;
  contact.translation_m = Eigen::Vector3d(-47.71, 0.0, -18.9);
  const std::vector<RenderItem> items = {
      {renderer.AddModel(LoadSceneModel(SourcePath("scenes/c12.glb"))), IsometryFromPose(contact), 1.0f}};
  const MsaaPlan x1 = PlanMsaa(1, context.info().color_sample_counts);
  const LinearImage still = renderer.RenderColor(rig.left, rig.near_m, items, x1);
  const LinearImage exposed = renderer.RenderExposure(rig.left, rig.near_m, {items, items, items, items}, x1);
  EXPECT_TRUE(still.rgb == exposed.rgb);
  const MsaaPlan x8 = PlanMsaa(8, context.info().color_sample_counts);
  if (x8.passes == 2) {  // lavapipe: x8 is two jittered x4 passes
    EXPECT_NE(ErrorOf([&] {
                renderer.RenderExposure(rig.left, rig.near_m, {items, items, items}, x8);
              }).find("3 instants and 2 MSAA passes"),
              std::string::npos);
  }
}

// Frame 500 of the CONOPS path (region C, 19.6 m) three ways: without
// propellers, with them frozen (an instant), with them turning over a 4 ms
// shutter. The propellers are the receiver's in the mask; the truth is the
// sample time's whatever the shutter; the shutter smears the dark blades
// over a larger, lighter disc.
TEST(Exposure, PropellersAreTheReceiversAndTheShutterBlursThem) {
  TempDir dir;
  const auto render = [&](const std::string& name, double rpm, double shutter_ms) {
    RenderJobOptions o;
    o.output = dir / name;
    o.rig = SourcePath("scenes/rig.json");
    o.receiver_model = SourcePath("scenes/c12.glb");
    o.tanker_model = SourcePath("scenes/kc46.glb");
    o.propeller_model = SourcePath("scenes/c12_propeller.glb");
    o.flight_path = SourcePath("flightpaths/conops.csv");
    o.selection = ParseFrameSelection("500:501", "");
    o.msaa = 1;
    o.depth = true;
    o.propeller_rpm = rpm;
    o.shutter_ms = shutter_ms;
    o.time_samples = 8;
    o.progress = false;
    RenderFlightPathJob(o);
    return o.output;
  };
  const auto plain = render("plain", 0.0, 0.0), frozen = render("frozen", 1700.0, 0.0),
             blurred = render("blurred", 1700.0, 4.0);
  const auto manifest = [](const std::filesystem::path& d) {
    return nlohmann::json::parse(ReadFileBytes(d / kManifestName));
  };
  EXPECT_FALSE(manifest(plain).at("frames").contains("propellers"));
  EXPECT_FALSE(manifest(plain).at("frames").contains("exposure"));
  EXPECT_FALSE(manifest(plain).at("inputs").contains("propeller_model"));
  EXPECT_EQ(manifest(frozen).at("frames").at("propellers").at("rpm"), 1700.0);
  EXPECT_FALSE(manifest(frozen).at("frames").contains("exposure"));
  EXPECT_EQ(manifest(blurred).at("frames").at("exposure").at("shutter_ms"), 4.0);
  EXPECT_EQ(manifest(blurred).at("frames").at("exposure").at("time_samples"), 8);

  const auto read = [](const std::filesystem::path& d, const std::string& file) {
    return cv::imread((d / kFramesDir / ("000500_" + file)).string(), cv::IMREAD_UNCHANGED);
  };
  // Mask: more receiver pixels (id 1) with the propellers, the same with or without the shutter.
  const auto receiver_pixels = [](const cv::Mat& mask) { return static_cast<size_t>(cv::countNonZero(mask == 1)); };
  const size_t without = receiver_pixels(read(plain, "left_mask.png"));
  const size_t with = receiver_pixels(read(frozen, "left_mask.png"));
  EXPECT_GT(with, without + 500) << without << " -> " << with;
  EXPECT_EQ(ReadFileBytes(frozen / kFramesDir / "000500_left_mask.png"),
            ReadFileBytes(blurred / kFramesDir / "000500_left_mask.png"));
  EXPECT_EQ(ReadFileBytes(frozen / kFramesDir / "000500_left_depth.exr"),
            ReadFileBytes(blurred / kFramesDir / "000500_left_depth.exr"));

  // Colour: pixels the propellers change (more than 8 codes from the plain
  // image) and, of those, the ones they darken by more than 60 codes.
  const cv::Mat base = read(plain, "left.png");
  // Mean of the three channels' change from the plain image, in codes, per pixel.
  const auto count = [&](const cv::Mat& image, const std::function<bool(int)>& keep) {
    size_t n = 0;
    for (int y = 0; y < image.rows; ++y) {
      for (int x = 0; x < image.cols; ++x) {
        const cv::Vec3b a = image.at<cv::Vec3b>(y, x), b = base.at<cv::Vec3b>(y, x);
        n += keep((a[0] + a[1] + a[2] - b[0] - b[1] - b[2]) / 3);
      }
    }
    return n;
  };
  const auto changed = [&](const cv::Mat& image) { return count(image, [](int d) { return std::abs(d) > 8; }); };
  const auto darkened = [&](const cv::Mat& image) { return count(image, [](int d) { return d < -60; }); };
  const cv::Mat frozen_image = read(frozen, "left.png"), blurred_image = read(blurred, "left.png");
  std::printf("pixels changed: frozen %zu, blurred %zu; darkened by > 60 codes: frozen %zu, blurred %zu\n",
              changed(frozen_image), changed(blurred_image), darkened(frozen_image), darkened(blurred_image));
  EXPECT_GT(changed(blurred_image), changed(frozen_image) * 3 / 2);
  EXPECT_LT(darkened(blurred_image), darkened(frozen_image) / 2);
}

}  // namespace
}  // namespace aar
