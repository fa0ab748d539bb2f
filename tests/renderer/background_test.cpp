// Backgrounds (docs/rendering.md, "Backgrounds"): the horizon where altitude
// and attitude put it, depth and ids of the ground and the cloud deck, no seam
// between the background pass and the aircraft's MSAA passes, determinism,
// the manifest, the textures, and the flat default untouched.

#include "aar/renderer/background.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "../test_support.h"
#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/pose.h"
#include "aar/renderer/background_texture.h"
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

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

RenderJobOptions Options(const std::filesystem::path& output, const std::filesystem::path& path) {
  RenderJobOptions o;
  o.output = output;
  o.rig = SourcePath("scenes/rig.json");
  o.receiver_model = SourcePath("scenes/c12.glb");
  o.tanker_model = SourcePath("scenes/kc46.glb");
  o.flight_path = path;
  o.progress = false;
  o.msaa = 1;
  return o;
}

// Frame 0: the receiver at the contact position; frame 1: 200 m ahead of the tanker, out of both views.
std::filesystem::path WritePath(const TempDir& dir) {
  const std::filesystem::path path = dir / "path.csv";
  WriteFileAtomic(path,
                  "time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg\n"
                  "0.0,-47.71,0.0,-18.9,0.0,0.0,0.0\n"
                  "0.5,200.0,0.0,0.0,0.0,0.0,0.0\n");
  return path;
}

cv::Mat ReadGrey(const std::filesystem::path& path) { return cv::imread(path.string(), cv::IMREAD_UNCHANGED); }

cv::Mat ReadDepth(const std::filesystem::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  EXPECT_TRUE(in) << path;
  cv::Mat depth(in->spec().height, in->spec().width, CV_32F);
  EXPECT_TRUE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, depth.data));
  return depth;
}

std::filesystem::path FramePath(const std::filesystem::path& dataset, size_t index, const std::string& role) {
  return dataset / ReadSidecar(SidecarPath(dataset, "frame", index)).files.at(role).path;
}

// Depth along the optical axis, in the test's own arithmetic: the near root of
// |p + s u|^2 = R^2 (p the camera R + h above the centre, u the unit ray of
// depression `depression` below the horizontal), times cos(angle off the axis).
double SphereDepth(double height_m, double radius_m, double depression, double off_axis) {
  const double dz = -std::sin(depression);
  const double b = (radius_m + height_m) * dz;
  const double c = (radius_m + height_m) * (radius_m + height_m) - radius_m * radius_m;
  return (-b - std::sqrt(b * b - c)) * std::cos(off_axis);
}

TEST(Background, SphereHitAndHorizonDipMatchGeometry) {
  const double h = 7000.0;
  const double dip = HorizonDipRad(h);
  EXPECT_NEAR(dip / kDeg, 2.6846, 1e-3);  // acos(6371 / 6378.0029) km
  const Eigen::Vector3d down(0.0, 0.0, -2.0);
  ASSERT_TRUE(SphereHitParameter(down, h).has_value());
  EXPECT_NEAR(*SphereHitParameter(down, h) * 2.0, h, 1e-6);
  EXPECT_FALSE(SphereHitParameter(Eigen::Vector3d(std::cos(dip - 1e-6), 0, -std::sin(dip - 1e-6)), h).has_value());
  const Eigen::Vector3d just_below(std::cos(dip + 1e-6), 0, -std::sin(dip + 1e-6));
  ASSERT_TRUE(SphereHitParameter(just_below, h).has_value());
  EXPECT_NEAR(*SphereHitParameter(just_below, h), std::sqrt(2.0 * kEarthRadiusM * h),
              0.05 * std::sqrt(2.0 * kEarthRadiusM * h));
  const double depression = 30.0 * kDeg;
  EXPECT_NEAR(*SphereHitParameter(Eigen::Vector3d(std::cos(depression), 0, -std::sin(depression)), h),
              SphereDepth(h, kEarthRadiusM, depression, 0.0), 1e-6);
}

TEST(Background, HazeFollowsKoschmiederAndHeight) {
  BackgroundOptions o;
  o.visibility_m = 20000.0;
  // At sea level, horizontally, 2 % contrast is left at the visibility.
  EXPECT_NEAR(std::exp(-HazeOpticalDepth(20000.0, 0.0, 0.0, o)), 0.02, 1e-4);
  // Looking down from 7 km the haze is thinner than at sea level over the same length.
  EXPECT_LT(HazeOpticalDepth(14000.0, 7000.0, 0.0, o), 0.25 * HazeOpticalDepth(14000.0, 0.0, 0.0, o));
  EXPECT_NEAR(HazeOpticalDepth(14000.0, 7000.0, 0.0, o), HazeOpticalDepth(14000.0, 0.0, 7000.0, o), 1e-12);
}

// Tanker 20 deg nose down: the aft cameras look 10 deg down, and the horizon
// (2.69 deg below the horizontal at 7 km) crosses the image centre column at
// v* = cy + fy tan(dip - depression_of_axis) = 268.1.
TEST(Background, HorizonAtTheRowAltitudeAndPitchPredict) {
  TempDir dir("background-horizon");
  RenderJobOptions o = Options(dir / "ds", WritePath(dir));
  o.background.kind = BackgroundKind::kTerrain;
  o.background.altitude_m = 7000.0;
  o.background.tanker_pitch_deg = 20.0;
  o.depth = true;
  o.selection.begin = 1;
  RenderFlightPathJob(o);

  const StereoRig rig = LoadRig(o.rig);
  const Intrinsics& k = rig.left.intrinsics;
  const Eigen::Matrix3d level_from_tanker = RotationFromRollPitchYaw(0.0, 20.0, 0.0);
  const Eigen::Vector3d axis = level_from_tanker * rig.left.tanker_from_camera.linear().col(2);
  const double axis_depression = -std::asin(axis.z());
  const double camera_height = 7000.0 + (level_from_tanker * rig.left.tanker_from_camera.translation()).z();
  const double dip = std::acos(kEarthRadiusM / (kEarthRadiusM + camera_height));
  const double v_horizon = k.cy_px + k.fy_px * std::tan(dip - axis_depression);
  EXPECT_NEAR(v_horizon, 268.1, 0.5);

  const cv::Mat mask = ReadGrey(FramePath(o.output, 1, "left_mask"));
  const cv::Mat depth = ReadDepth(FramePath(o.output, 1, "left_depth"));
  const int u = static_cast<int>(std::lround(k.cx_px));
  int first_ground = -1;
  for (int v = 0; v < mask.rows; ++v) {
    if (mask.at<uint8_t>(v, u) == kGroundId) {
      first_ground = v;
      break;
    }
  }
  // Row v's centre is below the horizon from the first integer past v*.
  EXPECT_NEAR(first_ground, v_horizon, 1.0);
  for (int v = 0; v < mask.rows; ++v) {
    const bool below = v >= first_ground;
    ASSERT_EQ(mask.at<uint8_t>(v, u), below ? kGroundId : 0) << "row " << v;
    if (!below) {
      ASSERT_EQ(depth.at<float>(v, u), 0.0f) << "row " << v;
    }
  }
  // Depth truth at the bottom row: the distance to the sphere along the optical axis.
  const double off_axis = std::atan((mask.rows - 1 - k.cy_px) / k.fy_px);
  const double expected = SphereDepth(camera_height, kEarthRadiusM, axis_depression + off_axis, off_axis);
  EXPECT_NEAR(depth.at<float>(mask.rows - 1, u), expected, 1e-4 * expected);

  // The colour image: sky above the horizon brighter and bluer than the hazy ground far below it.
  const cv::Mat left = cv::imread(FramePath(o.output, 1, "left").string(), cv::IMREAD_COLOR);
  const cv::Vec3b sky = left.at<cv::Vec3b>(first_ground - 40, u);
  const cv::Vec3b ground = left.at<cv::Vec3b>(mask.rows - 1, u);
  EXPECT_GT(sky[0], ground[0] + 20);  // BGR: blue
}

// Sky: the same horizon, and below it plain ground (id 4) without texture:
// along an image row the colour varies only with the haze, smoothly.
TEST(Background, SkyHasAHorizonAndPlainGround) {
  TempDir dir("background-sky");
  RenderJobOptions o = Options(dir / "ds", WritePath(dir));
  o.background.kind = BackgroundKind::kSky;
  o.background.tanker_pitch_deg = 20.0;
  o.depth = true;
  o.selection.begin = 1;
  RenderFlightPathJob(o);
  const cv::Mat mask = ReadGrey(FramePath(o.output, 1, "left_mask"));
  EXPECT_EQ(mask.at<uint8_t>(100, 512), 0);
  EXPECT_EQ(mask.at<uint8_t>(700, 512), kGroundId);
  cv::Mat grey;
  cv::cvtColor(cv::imread(FramePath(o.output, 1, "left").string(), cv::IMREAD_COLOR), grey, cv::COLOR_BGR2GRAY);
  int largest_step = 0;
  for (int u = 1; u < grey.cols; ++u)
    largest_step = std::max(largest_step, std::abs(grey.at<uint8_t>(700, u) - grey.at<uint8_t>(700, u - 1)));
  EXPECT_LE(largest_step, 1);
}

// Clouds: below the horizon every ray meets the deck top (id 5) at its depth.
TEST(Background, CloudDeckHasItsIdAndDepth) {
  TempDir dir("background-clouds");
  RenderJobOptions o = Options(dir / "ds", WritePath(dir));
  o.background.kind = BackgroundKind::kClouds;
  o.background.cloud_top_m = 3000.0;
  o.depth = true;
  RenderFlightPathJob(o);
  const StereoRig rig = LoadRig(o.rig);
  const Intrinsics& k = rig.left.intrinsics;
  const cv::Mat mask = ReadGrey(FramePath(o.output, 0, "left_mask"));
  const cv::Mat depth = ReadDepth(FramePath(o.output, 0, "left_depth"));
  // Level tanker: the top of the image is 6.9 deg below the horizontal, below the horizon: all deck or aircraft.
  for (int v = 0; v < mask.rows; ++v) {
    for (int u = 0; u < mask.cols; ++u) {
      const uint8_t id = mask.at<uint8_t>(v, u);
      ASSERT_TRUE(id == kCloudDeckId || id == 1) << u << "," << v << ": id " << int(id);
    }
  }
  const Eigen::Vector3d axis = rig.left.tanker_from_camera.linear().col(2);
  const double camera_height = 7000.0 + rig.left.tanker_from_camera.translation().z() - 3000.0;
  const double off_axis = std::atan((0 - k.cy_px) / k.fy_px);
  const double expected = SphereDepth(camera_height, kEarthRadiusM + 3000.0, -std::asin(axis.z()) + off_axis, off_axis);
  EXPECT_NEAR(depth.at<float>(0, static_cast<int>(k.cx_px)), expected, 1e-4 * expected);
  // The manifest records the background and its seed.
  const nlohmann::json manifest = nlohmann::json::parse(ReadFileBytes(o.output / kManifestName));
  const nlohmann::json& bg = manifest.at("frames").at("background");
  EXPECT_EQ(bg.at("kind"), "clouds");
  EXPECT_EQ(bg.at("cloud_top_m"), 3000.0);
  EXPECT_EQ(bg.at("seed"), 1);
  EXPECT_EQ(bg.at("mask_ids").at("cloud_deck"), kCloudDeckId);
}

// At x16 (4 jittered passes of x4 on lavapipe) the background inside the
// receiver's MSAA rectangle equals the single-sample pass outside it: away
// from the receiver the view with it equals the view without it, exactly.
TEST(Background, NoSeamAroundTheAircraftRectangle) {
  VulkanContext context{VulkanContextOptions{}};
  const StereoRig rig = LoadRig(SourcePath("scenes/rig.json"));
  const int width = rig.left.intrinsics.width_px, height = rig.left.intrinsics.height_px;
  SceneRendererOptions options;
  options.background.kind = BackgroundKind::kTerrain;
  SceneRenderer renderer(context, width, height, options);
  const int receiver = renderer.AddModel(LoadSceneModel(SourcePath("scenes/c12.glb")));
  Pose contact;
  contact.translation_m = Eigen::Vector3d(-47.71, 0.0, -18.9);
  const std::vector<RenderItem> items = {{receiver, IsometryFromPose(contact), 1.0f}};
  const MsaaPlan plan = PlanMsaa(16, context.info().color_sample_counts);
  const LinearImage with = renderer.RenderColor(rig.left, rig.near_m, items, plan);
  const LinearImage without = renderer.RenderColor(rig.left, rig.near_m, {}, plan);
  const GroundTruthImage truth = renderer.RenderGroundTruth(rig.left, rig.near_m, items);
  cv::Mat receiver_mask(height, width, CV_8U);
  for (int i = 0; i < width * height; ++i) receiver_mask.data[i] = truth.object_id[i] == 1 ? 255 : 0;
  cv::dilate(receiver_mask, receiver_mask, cv::Mat::ones(5, 5, CV_8U));  // samples reach past the pixel centre
  size_t compared = 0, differing = 0, inside_differing = 0;
  for (int i = 0; i < width * height; ++i) {
    const bool same = std::equal(&with.rgb[i * 3], &with.rgb[i * 3 + 3], &without.rgb[i * 3]);
    if (receiver_mask.data[i]) {
      inside_differing += same ? 0 : 1;
      continue;
    }
    ++compared;
    differing += same ? 0 : 1;
  }
  EXPECT_GT(compared, 500000u);
  EXPECT_EQ(differing, 0u);
  EXPECT_GT(inside_differing, 10000u);  // the receiver is there
  // The terrain is textured, unlike the flat sky: its luminance varies.
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < width * height; ++i) {
    const double y = without.rgb[i * 3 + 1];
    sum += y;
    sum2 += y * y;
  }
  const double mean = sum / (width * height);
  EXPECT_GT(std::sqrt(sum2 / (width * height) - mean * mean), 0.01 * mean);
}

TEST(Background, SameInputsGiveByteIdenticalDatasetsAndTheSeedMatters) {
  TempDir dir("background-determinism");
  const std::filesystem::path path = WritePath(dir);
  std::vector<std::map<std::string, std::string>> files;
  for (uint32_t seed : {7u, 7u, 8u}) {
    RenderJobOptions o = Options(dir / ("ds" + std::to_string(files.size())), path);
    o.background.kind = BackgroundKind::kTerrain;
    o.background.seed = seed;
    o.msaa = 4;
    o.depth = true;
    RenderFlightPathJob(o);
    files.push_back(ReadManifest(o.output).files);
  }
  EXPECT_EQ(files[0], files[1]);
  EXPECT_NE(files[0].at("frames/000000_left.png"), files[2].at("frames/000000_left.png"));
  EXPECT_EQ(files[0].at("frames/000000_left_mask.png"), files[2].at("frames/000000_left_mask.png"));
}

// The background depends on the camera alone, so it is rendered once per
// camera and reused for the following frames: frame 1 of a run that rendered
// frame 0 first is the same, byte for byte, as frame 1 rendered alone.
TEST(Background, ReusedBackgroundEqualsAFreshlyRenderedOne) {
  TempDir dir("background-reuse");
  const std::filesystem::path path = WritePath(dir);
  std::vector<std::filesystem::path> datasets;
  for (size_t begin : {0u, 1u}) {
    RenderJobOptions o = Options(dir / ("from" + std::to_string(begin)), path);
    o.background.kind = BackgroundKind::kTerrain;
    o.msaa = 4;
    o.selection.begin = begin;
    RenderFlightPathJob(o);
    datasets.push_back(o.output);
  }
  for (const char* side : {"left", "right"}) {
    EXPECT_EQ(ReadFileBytes(FramePath(datasets[0], 1, side)), ReadFileBytes(FramePath(datasets[1], 1, side))) << side;
  }
  EXPECT_NE(ReadFileBytes(FramePath(datasets[0], 1, "left")), ReadFileBytes(FramePath(datasets[0], 1, "right")));
}

// The flat default: no `background` key in the manifest (datasets made before
// backgrounds still match), sky id 0 with depth 0, nothing else but aircraft.
TEST(Background, FlatDefaultHasNoBackgroundInManifestOrMasks) {
  TempDir dir("background-flat");
  RenderJobOptions o = Options(dir / "ds", WritePath(dir));
  o.depth = true;
  o.selection.end = 1;
  RenderFlightPathJob(o);
  const nlohmann::json manifest = nlohmann::json::parse(ReadFileBytes(o.output / kManifestName));
  EXPECT_FALSE(manifest.at("frames").contains("background"));
  const cv::Mat mask = ReadGrey(FramePath(o.output, 0, "left_mask"));
  const cv::Mat depth = ReadDepth(FramePath(o.output, 0, "left_depth"));
  for (int v = 0; v < mask.rows; ++v) {
    for (int u = 0; u < mask.cols; ++u) {
      const uint8_t id = mask.at<uint8_t>(v, u);
      ASSERT_TRUE(id == 0 || id == 1) << u << "," << v;
      if (id == 0) {
        ASSERT_EQ(depth.at<float>(v, u), 0.0f);
      }
    }
  }
}

TEST(Background, SunDirectionFollowsAzimuthAndElevation) {
  BackgroundOptions o;
  EXPECT_TRUE(SunInLevel(o).isApprox(Eigen::Vector3d(0.35, 0.45, 0.82).normalized(), 1e-15));  // the default
  o.sun = SunOptions{90.0, 0.0, "test"};  // to the right of the heading: -y in the level frame
  EXPECT_TRUE(SunInLevel(o).isApprox(Eigen::Vector3d(0.0, -1.0, 0.0), 1e-12)) << SunInLevel(o).transpose();
  o.sun = SunOptions{180.0, 30.0, "test"};  // behind, 30 deg up
  EXPECT_TRUE(SunInLevel(o).isApprox(Eigen::Vector3d(-std::cos(30 * kDeg), 0.0, 0.5), 1e-12));
  o.sun->elevation_deg = -1.0;
  EXPECT_THROW(o.Check(), Error);
}

// The receiver's top, which the cameras look down on, is brighter under a
// sun 30 deg up aft of the tanker than under a sun 5 deg up ahead of it, and
// the manifest records the sun it was lit by.
TEST(Background, TheSunLightsTheReceiverFromWhereItIsSet) {
  TempDir dir("background-sun");
  const std::filesystem::path path = WritePath(dir);
  const auto receiver_brightness = [&](const std::string& name, std::optional<SunOptions> sun) {
    RenderJobOptions o = Options(dir / name, path);
    o.depth = true;
    o.selection.end = 1;
    o.background.sun = std::move(sun);
    RenderFlightPathJob(o);
    const cv::Mat image = cv::imread(FramePath(o.output, 0, "left").string(), cv::IMREAD_GRAYSCALE);
    const cv::Mat silhouette = ReadGrey(FramePath(o.output, 0, "left_silhouette"));
    EXPECT_GT(cv::countNonZero(silhouette), 1000);
    return cv::mean(image, silhouette)[0];
  };
  const double high_aft = receiver_brightness("high-aft", SunOptions{180.0, 30.0, "test"});
  const double low_ahead = receiver_brightness("low-ahead", SunOptions{0.0, 5.0, "test"});
  EXPECT_GT(high_aft, 1.1 * low_ahead) << high_aft << " " << low_ahead;
  const nlohmann::json manifest = nlohmann::json::parse(ReadFileBytes(dir / "low-ahead" / kManifestName));
  const nlohmann::json& sun = manifest.at("frames").at("sun");
  EXPECT_EQ(sun.at("elevation_deg"), 5.0);
  EXPECT_NEAR(sun.at("in_level").at(2).get<double>(), std::sin(5.0 * kDeg), 1e-12);
  EXPECT_EQ(sun.at("source"), "test");
  RenderJobOptions plain = Options(dir / "plain", path);
  plain.selection.end = 1;
  RenderFlightPathJob(plain);
  EXPECT_FALSE(nlohmann::json::parse(ReadFileBytes(plain.output / kManifestName)).at("frames").contains("sun"));
}

TEST(BackgroundTexture, DeterministicPeriodicAndShowsFieldsRoadsWater) {
  const TextureMips a = TerrainTexture(3, 512);
  const TextureMips b = TerrainTexture(3, 512);
  const TextureMips c = TerrainTexture(4, 512);
  EXPECT_EQ(a.levels, b.levels);
  EXPECT_NE(a.levels[0], c.levels[0]);
  EXPECT_EQ(a.sizes.back(), (std::array<int, 2>{1, 1}));
  // Water (blue above red) and road (grey) texels are present but not dominant.
  size_t water = 0, road = 0;
  const std::vector<uint8_t>& t = a.levels[0];
  for (size_t i = 0; i < t.size(); i += 4) {
    if (t[i + 2] > t[i] + 15) ++water;
    if (std::abs(t[i] - t[i + 2]) < 12 && std::abs(t[i] - t[i + 1]) < 12 && t[i] > 85) ++road;
  }
  const double n = static_cast<double>(t.size() / 4);
  EXPECT_GT(water / n, 0.01);
  EXPECT_LT(water / n, 0.5);
  EXPECT_GT(road / n, 0.002);
  EXPECT_LT(road / n, 0.2);
  // Periodic: across the wrap (last column to first) neighbours differ no more than at a block edge inside.
  double wrap = 0.0, inside = 0.0;
  for (int y = 0; y < 512; ++y) {
    const size_t row = static_cast<size_t>(y) * 512 * 4;
    wrap += std::abs(t[row + 1] - t[row + 511 * 4 + 1]);
    inside += std::abs(t[row + 256 * 4 + 1] - t[row + 255 * 4 + 1]);
  }
  EXPECT_LT(wrap, 2.0 * inside);  // both pairs straddle a road column (x % 256 == 0)
  EXPECT_THROW(TerrainTexture(1, 300), Error);
  const TextureMips clouds = CloudTexture(1, 256);
  EXPECT_EQ(clouds.levels, CloudTexture(1, 256).levels);
}

}  // namespace
}  // namespace aar
