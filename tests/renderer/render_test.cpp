// Rendering on the default Vulkan device (lavapipe in CI): flight-path truth,
// projection accuracy against OpenCV, determinism, MSAA composition, resume
// and sharding.

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <set>

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

using test::SourcePath;
using test::TempDir;

RenderJobOptions DefaultOptions(const std::filesystem::path& output) {
  RenderJobOptions o;
  o.output = output;
  o.rig = SourcePath("scenes/rig.json");
  o.receiver_model = SourcePath("scenes/c12.glb");
  o.tanker_model = SourcePath("scenes/kc46.glb");
  o.board_model = SourcePath("scenes/calib_board.glb");
  o.far_boards_m = {};  // the twelve near boards: a third of the default's rendering time
  o.progress = false;
  return o;
}

// Three samples near the contact position (region C) and one in region B.
std::filesystem::path WriteShortPath(const TempDir& dir) {
  const std::filesystem::path path = dir / "short.csv";
  WriteFileAtomic(path,
                  "time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg\n"
                  "0.0,-47.71,0.0,-18.9,0.0,0.0,0.0\n"
                  "0.5,-48.2,0.3,-19.1,1.5,-1.0,2.0\n"
                  "1.0,-50.0,-0.5,-20.0,-2.0,1.0,-1.5\n"
                  "1.5,-60.0,1.0,-25.0,0.0,0.5,0.0\n");
  return path;
}

TEST(Render, ShortFlightPathSidecarsCarryTruth) {
  TempDir dir("render-short");
  RenderJobOptions o = DefaultOptions(dir / "ds");
  o.flight_path = WriteShortPath(dir);
  o.msaa = 1;
  o.depth_right = true;
  const RenderJobResult result = RenderFlightPathJob(o);
  EXPECT_EQ(result.rendered, 4u);
  EXPECT_TRUE(result.complete);
  const Manifest manifest = ReadManifest(o.output);
  EXPECT_TRUE(manifest.complete);
  EXPECT_EQ(manifest.frame_count, 4u);

  const FrameSidecar s1 = ReadSidecar(SidecarPath(o.output, "frame", 1));
  EXPECT_DOUBLE_EQ(s1.time_s, 0.5);
  EXPECT_DOUBLE_EQ(s1.tanker_from_target.translation_m.x(), -48.2);
  EXPECT_DOUBLE_EQ(s1.tanker_from_target.translation_m.y(), 0.3);
  EXPECT_DOUBLE_EQ(s1.tanker_from_target.roll_deg, 1.5);
  EXPECT_DOUBLE_EQ(s1.tanker_from_target.yaw_deg, 2.0);
  EXPECT_EQ(s1.region, "C");
  EXPECT_EQ(ReadSidecar(SidecarPath(o.output, "frame", 3)).region, "B");
  const Eigen::Vector3d left = s1.rig.left.tanker_from_camera.translation();
  EXPECT_NEAR(s1.range_m, (s1.tanker_from_target.translation_m - left).norm(), 1e-9);
  EXPECT_GT(s1.in_view_left, 0.99);

  // Every listed file exists with its hash; the images show something other than sky.
  for (const auto& [path, hash] : manifest.files) EXPECT_EQ(Sha256File(o.output / path), hash) << path;
  // SHA256SUMS lists the same files and the manifest, sorted, and `sha256sum -c` accepts it.
  std::string sums;
  std::map<std::string, std::string> expected = manifest.files;
  expected[kManifestName] = Sha256File(o.output / kManifestName);
  for (const auto& [path, hash] : expected) sums += hash + "  " + path + "\n";
  EXPECT_EQ(ReadFileBytes(o.output / kChecksumsName), sums);
  EXPECT_EQ(test::RunCommand("cd '" + o.output.string() + "' && sha256sum --quiet -c SHA256SUMS").exit_code, 0);

  // cam_from_receiver: the receiver origin projects where the rig's chain puts it, in both cameras.
  const nlohmann::json sidecar_json = ReadJsonFile(SidecarPath(o.output, "frame", 1));
  for (const char* side : {"left", "right"}) {
    const Camera& cam = std::string(side) == "left" ? s1.rig.left : s1.rig.right;
    const Eigen::Isometry3d expected_cam_from_receiver =
        cam.tanker_from_camera.inverse() * IsometryFromPose(s1.tanker_from_target);
    const Eigen::Isometry3d cam_from_receiver =
        IsometryFromJson(sidecar_json.at("cam_from_receiver").at(side), "sidecar");
    EXPECT_TRUE(cam_from_receiver.matrix().isApprox(expected_cam_from_receiver.matrix(), 1e-12)) << side;
    EXPECT_GT(cam_from_receiver.translation().z(), 25.0) << side;  // in front of the camera
  }
  const cv::Mat image = cv::imread((o.output / s1.files.at("left").path).string(), cv::IMREAD_COLOR);
  ASSERT_EQ(image.cols, 1024);
  ASSERT_EQ(image.rows, 768);

  // Depth truth at the image centre: the receiver, about 32 m away along the axis.
  auto in = OIIO::ImageInput::open((o.output / s1.files.at("left_depth").path).string());
  ASSERT_TRUE(in);
  std::vector<float> depth(1024 * 768);
  ASSERT_TRUE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, depth.data()));
  float nearest = 1e9f, farthest = 0.0f;
  for (float d : depth) {
    if (d > 0) {
      nearest = std::min(nearest, d);
      farthest = std::max(farthest, d);
    }
  }
  EXPECT_GT(nearest, 20.0f);
  EXPECT_LT(farthest, 45.0f);
  // OpenCV reads the EXR as it is: one float channel with the same values.
  const cv::Mat cv_depth = cv::imread((o.output / s1.files.at("left_depth").path).string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(cv_depth.type(), CV_32FC1);
  ASSERT_EQ(cv_depth.total(), depth.size());
  EXPECT_EQ(std::memcmp(cv_depth.data, depth.data(), depth.size() * sizeof(float)), 0);

  // The mask marks exactly the pixels with depth as receiver (no anti-aliased edge values).
  const cv::Mat mask = cv::imread((o.output / s1.files.at("left_mask").path).string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(mask.type(), CV_8UC1);
  for (int i = 0; i < 1024 * 768; ++i) {
    const uint8_t id = mask.data[i];
    ASSERT_TRUE(id == 0 || id == 1) << "pixel " << i << " has id " << int(id);
    ASSERT_EQ(id == 1, depth[i] > 0) << "pixel " << i;
  }
  // The silhouette of the receiver alone covers every receiver pixel of the mask, in both cameras.
  for (const char* side : {"left", "right"}) {
    const std::string role = side;
    const cv::Mat ids = cv::imread((o.output / s1.files.at(role + "_mask").path).string(), cv::IMREAD_UNCHANGED);
    const cv::Mat silhouette =
        cv::imread((o.output / s1.files.at(role + "_silhouette").path).string(), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(silhouette.type(), CV_8UC1) << side;
    const int receiver = cv::countNonZero(ids == 1);
    EXPECT_GT(receiver, 10000) << side;
    EXPECT_EQ(cv::countNonZero((ids == 1) & (silhouette != 255)), 0) << side;
    EXPECT_EQ(cv::countNonZero((silhouette != 0) & (silhouette != 255)), 0) << side;
    EXPECT_TRUE(std::filesystem::is_regular_file(o.output / s1.files.at(role + "_depth").path)) << side;
  }
}

// RMS distance of the detected board corners in rendered x16 calibration
// images from cv::projectPoints of the true board corners (the rig's
// intrinsics and lens distortion, the true board pose).
double CalibrationCornerRmsAtX16(const std::string& rig, const std::string& name) {
  TempDir dir(name);
  RenderJobOptions o = DefaultOptions(dir / "ds");
  o.rig = SourcePath(rig);
  o.msaa = 16;
  RenderCalibrationJob(o);
  const Manifest manifest = ReadManifest(o.output);
  EXPECT_GE(manifest.calib_pair_count, 10u);
  double sum_sq = 0.0;
  size_t count = 0;
  for (size_t i = 0; i < manifest.calib_pair_count; ++i) {
    const FrameSidecar s = ReadSidecar(SidecarPath(o.output, "calib", i));
    for (const char* side : {"left", "right"}) {
      const Camera& cam = std::string(side) == "left" ? s.rig.left : s.rig.right;
      const cv::Mat gray = cv::imread((o.output / s.files.at(side).path).string(), cv::IMREAD_GRAYSCALE);
      std::vector<cv::Point2f> corners;
      const bool found = cv::findChessboardCorners(gray, cv::Size(16, 17), corners, cv::CALIB_CB_ADAPTIVE_THRESH);
      EXPECT_TRUE(found) << s.files.at(side).path;
      if (!found) return INFINITY;
      cv::cornerSubPix(gray, corners, cv::Size(11, 11), cv::Size(-1, -1),
                       cv::TermCriteria(cv::TermCriteria::EPS | cv::TermCriteria::COUNT, 100, 1e-4));
      std::vector<cv::Point3f> object;
      for (int j = 0; j < 17; ++j)
        for (int k = 0; k < 16; ++k) object.emplace_back(0.5f * k, 0.5f * j, 0.0f);
      const Eigen::Isometry3d cam_from_board =
          cam.tanker_from_camera.inverse() * IsometryFromPose(s.tanker_from_target);
      cv::Mat r(3, 3, CV_64F), rvec, tvec(3, 1, CV_64F);
      for (int a = 0; a < 3; ++a) {
        tvec.at<double>(a) = cam_from_board.translation()(a);
        for (int b = 0; b < 3; ++b) r.at<double>(a, b) = cam_from_board.linear()(a, b);
      }
      cv::Rodrigues(r, rvec);
      const cv::Mat k = (cv::Mat_<double>(3, 3) << cam.intrinsics.fx_px, 0, cam.intrinsics.cx_px, 0,
                         cam.intrinsics.fy_px, cam.intrinsics.cy_px, 0, 0, 1);
      const std::array<double, 5> d = cam.intrinsics.distortion.OpenCvOrder();
      const cv::Mat distortion = (cv::Mat_<double>(1, 5) << d[0], d[1], d[2], d[3], d[4]);
      std::vector<cv::Point2f> projected;
      cv::projectPoints(object, rvec, tvec, k, distortion, projected);
      // OpenCV may list the corners from either end; compare in the matching order.
      double forward = 0.0, backward = 0.0;
      for (size_t c = 0; c < corners.size(); ++c) {
        forward += std::pow(cv::norm(corners[c] - projected[c]), 2);
        backward += std::pow(cv::norm(corners[corners.size() - 1 - c] - projected[c]), 2);
      }
      sum_sq += std::min(forward, backward);
      count += corners.size();
    }
  }
  const double rms = std::sqrt(sum_sq / static_cast<double>(count));
  std::printf("%s: corner RMS vs projectPoints at x16: %.4f px over %zu corners\n", rig.c_str(), rms, count);
  return rms;
}

TEST(Render, CalibrationCornersMatchProjectionAtX16) {
  EXPECT_LT(CalibrationCornerRmsAtX16("scenes/rig.json", "render-calib"), 0.25);
}

// The same through the lens: rendered as a pinhole image with a margin and
// resampled into the distorted frame, the corners lie where cv::projectPoints
// with the true distortion puts them (40 px from the pinhole's at the corners).
TEST(Render, DistortedCalibrationCornersMatchProjectionAtX16) {
  EXPECT_LT(CalibrationCornerRmsAtX16("scenes/rig-distorted.json", "render-calib-lens"), 0.25);
}

TEST(Render, SameInputsGiveByteIdenticalDatasets) {
  TempDir dir("render-determinism");
  std::string first;
  for (const char* name : {"a", "b"}) {
    RenderJobOptions o = DefaultOptions(dir / name);
    o.flight_path = WriteShortPath(dir);
    o.msaa = 8;
    o.depth_right = true;  // depth EXRs carry no time stamp either
    o.selection.end = 2;
    RenderFlightPathJob(o);
    const std::string manifest = ReadFileBytes(o.output / kManifestName);
    if (first.empty()) {
      first = manifest;
    } else {
      EXPECT_EQ(manifest, first);
    }
  }
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir / "a")) {
    if (!entry.is_regular_file()) continue;
    const auto relative = std::filesystem::relative(entry.path(), dir / "a");
    EXPECT_EQ(ReadFileBytes(entry.path()), ReadFileBytes(dir / "b" / relative)) << relative;
  }
}

// A distorted rig: the same inputs give the same bytes, the manifest records
// the lens (a pinhole rig's has no lens entry), and the truth images hold only
// object ids and depths the pinhole pass produces (nearest, never blended).
TEST(Render, DistortedRigIsDeterministicAndRecordedInTheManifest) {
  TempDir dir("render-lens");
  for (const char* name : {"a", "b"}) {
    RenderJobOptions o = DefaultOptions(dir / name);
    o.rig = SourcePath("scenes/rig-distorted.json");
    o.flight_path = WriteShortPath(dir);
    o.msaa = 4;
    o.depth = true;
    o.selection.end = 1;
    RenderFlightPathJob(o);
  }
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir / "a")) {
    if (!entry.is_regular_file()) continue;
    const auto relative = std::filesystem::relative(entry.path(), dir / "a");
    EXPECT_EQ(ReadFileBytes(entry.path()), ReadFileBytes(dir / "b" / relative)) << relative;
  }
  const nlohmann::json manifest = nlohmann::json::parse(ReadFileBytes(dir / "a" / kManifestName));
  const nlohmann::json& lens = manifest.at("image").at("lens");
  EXPECT_EQ(lens.at("left"), nlohmann::json({-0.15, 0.05, 1e-4, -1e-4, 0.0}));
  EXPECT_EQ(lens.at("right"), nlohmann::json({-0.14, 0.045, -1.2e-4, 0.8e-4, 0.0}));
  EXPECT_GT(lens.at("pinhole_render").at("width").get<int>(), 1024);
  EXPECT_GT(lens.at("pinhole_render").at("height").get<int>(), 768);
  const cv::Mat ids = cv::imread((dir / "a/frames/000000_left_mask.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_FALSE(ids.empty());
  auto in = OIIO::ImageInput::open((dir / "a/frames/000000_left_depth.exr").string());
  ASSERT_TRUE(in);
  cv::Mat depth(ids.rows, ids.cols, CV_32F);
  ASSERT_TRUE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, depth.data));
  EXPECT_GT(cv::countNonZero(ids == 1), 10000);
  EXPECT_EQ(cv::countNonZero((ids != 0) & (ids != 1) & (ids != 2)), 0);
  EXPECT_EQ(cv::countNonZero((ids == 0) != (depth == 0.0f)), 0);  // surface exactly where an object is

  RenderJobOptions pinhole = DefaultOptions(dir / "pinhole");
  pinhole.flight_path = WriteShortPath(dir);
  pinhole.msaa = 1;
  pinhole.selection.end = 1;
  RenderFlightPathJob(pinhole);
  EXPECT_FALSE(nlohmann::json::parse(ReadFileBytes(pinhole.output / kManifestName)).at("image").contains("lens"));
}

// Only the rectangle that can hold geometry is rendered with MSAA (the
// tanker, whose box contains the cameras, adds nothing to it): a flight-path
// view, tanker and receiver, composed x8 (2 jittered passes on lavapipe), is
// the same to the last bit as the view rendered over the whole frame, over
// the flat sky and over terrain.
TEST(Render, GeometryRectangleGivesTheFullFrameImages) {
  VulkanContext context{VulkanContextOptions{}};
  const StereoRig rig = LoadRig(SourcePath("scenes/rig.json"));
  const SceneModel receiver = LoadSceneModel(SourcePath("scenes/c12.glb"));
  const SceneModel tanker = LoadSceneModel(SourcePath("scenes/kc46.glb"));
  Pose contact;
  contact.translation_m = Eigen::Vector3d(-47.71, 0.0, -18.9);
  const MsaaPlan plan = PlanMsaa(8, context.info().color_sample_counts);
  for (BackgroundKind kind : {BackgroundKind::kFlat, BackgroundKind::kTerrain}) {
    std::vector<LinearImage> views;
    for (bool full_frame : {false, true}) {
      SceneRendererOptions options;
      options.background.kind = kind;
      options.full_frame = full_frame;
      SceneRenderer renderer(context, rig.left.intrinsics.width_px, rig.left.intrinsics.height_px, options);
      const std::vector<RenderItem> items = {{renderer.AddModel(tanker), Eigen::Isometry3d::Identity(), 2.0f},
                                             {renderer.AddModel(receiver), IsometryFromPose(contact), 1.0f}};
      views.push_back(renderer.RenderColor(rig.right, rig.near_m, items, plan));
    }
    EXPECT_TRUE(views[0].rgb == views[1].rgb) << BackgroundName(kind);
    if (kind == BackgroundKind::kFlat) {  // the view holds the receiver, not only sky
      size_t receiver_pixels = 0;
      for (size_t i = 3; i < views[0].rgb.size(); i += 3) receiver_pixels += views[0].rgb[i] != views[0].rgb[0];
      EXPECT_GT(receiver_pixels, 10000u);
    }
  }
}

// Composed x16 yields partial-coverage colours along edges that x1 cannot.
TEST(Render, ComposedMsaaShowsIntermediateCoverage) {
  TempDir dir("render-msaa");
  std::map<int, size_t> distinct;
  for (int level : {1, 16}) {
    RenderJobOptions o = DefaultOptions(dir / ("x" + std::to_string(level)));
    o.msaa = level;
    o.selection.end = 1;
    RenderCalibrationJob(o);
    const cv::Mat gray = cv::imread((o.output / "calib/000000_left.png").string(), cv::IMREAD_GRAYSCALE);
    std::set<int> values(gray.begin<uint8_t>(), gray.end<uint8_t>());
    distinct[level] = values.size();
  }
  // The board is flat-shaded: without anti-aliasing only sky, black, white and
  // border shades occur; x16 adds many edge blends.
  std::printf("distinct grey levels: x1 %zu, x16 %zu\n", distinct[1], distinct[16]);
  EXPECT_LE(distinct[1], 8u);
  EXPECT_GE(distinct[16], 24u);
}

TEST(Render, ResumeSkipsCompleteFramesAndShardsMatchASingleRun) {
  TempDir dir("render-resume");
  const std::filesystem::path csv = WriteShortPath(dir);
  RenderJobOptions single = DefaultOptions(dir / "single");
  single.flight_path = csv;
  single.msaa = 1;
  RenderFlightPathJob(single);

  RenderJobOptions sharded = DefaultOptions(dir / "sharded");
  sharded.flight_path = csv;
  sharded.msaa = 1;
  sharded.selection = ParseFrameSelection("", "0/2");
  RenderJobResult r0 = RenderFlightPathJob(sharded);
  EXPECT_EQ(r0.rendered, 2u);
  EXPECT_FALSE(r0.complete);
  // A truncated image makes its frame unverified: it is rendered again.
  WriteFileAtomic(sharded.output / "frames/000000_left.png", "truncated");
  sharded.selection = ParseFrameSelection("", "");
  RenderJobResult all = RenderFlightPathJob(sharded);
  EXPECT_EQ(all.skipped, 1u);
  EXPECT_EQ(all.rendered, 3u);
  EXPECT_TRUE(all.complete);
  EXPECT_EQ(ReadFileBytes(sharded.output / kManifestName), ReadFileBytes(single.output / kManifestName));
}

}  // namespace
}  // namespace aar
