// Night (--night, --moonlight, --exposure-ev, --receiver-lights,
// --floodlight; docs/rendering.md "Exposure and night"): the camera's
// exposure factor, the moonlit sky as the daylight model scaled to the moon,
// the lights' places, intensities and flashes, a rendered light where it
// projects at its radiance, the floodlight's illuminance against the inverse
// square law on a rendered plate, and the manifest's record.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "../test_support.h"
#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/json_file.h"
#include "aar/renderer/background.h"
#include "aar/renderer/camera_exposure.h"
#include "aar/renderer/daylight.h"
#include "aar/renderer/floodlight.h"
#include "aar/renderer/msaa.h"
#include "aar/renderer/receiver_lights.h"
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
// The renderer's units: 0.75 for a white surface facing 133,800 lx (daylight.h).
constexpr double kUnitsPerLux = 0.75 / kSolarIlluminanceLx;

BackgroundOptions NightOver(BackgroundKind kind, double moonlight_lx) {
  BackgroundOptions b;
  b.kind = kind;
  b.sun = SunOptions{120.0, 35.0, "test"};
  b.daylight = DaylightOptions{};
  b.night = NightOptions{moonlight_lx};
  return b;
}

TEST(CameraExposure, ScalesByTwoToTheEvOverTheRenderScale) {
  const CameraExposure night(12.0, kNightRenderScale);
  EXPECT_FLOAT_EQ(night.factor(), 1.0f);  // 2^12 / 4096
  const CameraExposure day(-1.0, 1.0);
  LinearImage image{1, 1, {0.5f, 1.0f, 2.0f}};
  const LinearImage out = day.Apply(image, SensorExposure{});
  EXPECT_EQ(out.rgb, (std::vector<float>{0.25f, 0.5f, 1.0f}));
}

TEST(Night, IsTheDaylightModelScaledToTheMoon) {
  const Eigen::Vector3d albedo(0.2, 0.2, 0.2);
  BackgroundOptions day = NightOver(BackgroundKind::kTerrain, 0.25);
  day.night.reset();
  const BackgroundOptions night = NightOver(BackgroundKind::kTerrain, 0.25);
  const double scale = 0.25 / kSolarIlluminanceLx * kNightRenderScale;
  EXPECT_DOUBLE_EQ(SourceScale(night), scale);
  EXPECT_EQ(RenderScale(night), kNightRenderScale);
  EXPECT_EQ(RenderScale(day), 1.0);
  const Daylight d = ComputeDaylight(day, albedo), n = ComputeDaylight(night, albedo);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(n.sun_at_tanker[c], scale * d.sun_at_tanker[c], 1e-12 * d.sun_at_tanker[c]);
    EXPECT_NEAR(n.sky_from_above[c], scale * d.sky_from_above[c], 1e-9 * d.sky_from_above[c]);
    EXPECT_NEAR(n.sky_from_below[c], scale * d.sky_from_below[c], 1e-9 * d.sky_from_below[c]);
    EXPECT_NEAR(n.surface_light[c], scale * d.surface_light[c], 1e-9 * d.surface_light[c]);
  }
  // The moon's disc: smaller than the sun's, so brighter per steradian for the same light.
  EXPECT_EQ(n.disc_radius_rad, kMoonAngularRadiusRad);
  const double disc_ratio =
      kSunAngularRadiusRad * kSunAngularRadiusRad / (kMoonAngularRadiusRad * kMoonAngularRadiusRad);
  EXPECT_NEAR(n.sun_disc[1], scale * disc_ratio * d.sun_disc[1], 1e-9 * d.sun_disc[1]);
  // Moonlit white in render units: 0.75 x 0.25 / 133,800 x 4096, well above half floats' smallest normal.
  EXPECT_GT(n.sun_at_tanker.minCoeff(), 1e-3);
  // No moon, no light.
  EXPECT_EQ(ComputeDaylight(NightOver(BackgroundKind::kTerrain, 0.0), albedo).sky_from_above.maxCoeff(), 0.0);
}

TEST(Night, RefusesWhatItCannotRender) {
  BackgroundOptions flat = NightOver(BackgroundKind::kFlat, 0.25);
  flat.daylight.reset();
  EXPECT_THROW(flat.Check(), Error);
  BackgroundOptions no_daylight = NightOver(BackgroundKind::kSky, 0.25);
  no_daylight.daylight.reset();
  EXPECT_THROW(no_daylight.Check(), Error);
  EXPECT_THROW(NightOver(BackgroundKind::kSky, 1.5).Check(), Error);
  EXPECT_NO_THROW(NightOver(BackgroundKind::kSky, 0.0).Check());
}

// A box from -1 to 1 m in x, -2 to 2 in y, -0.5 to 0.5 in z.
SceneModel Box() {
  Primitive p;
  for (int i = 0; i < 8; ++i) {
    p.vertices.push_back(Vertex{{i & 1 ? 1.0f : -1.0f, i & 2 ? 2.0f : -2.0f, i & 4 ? 0.5f : -0.5f}, {0, 0, 1}, {0, 0}});
  }
  p.indices = {0, 1, 2};
  SceneModel model;
  model.path = "box";
  model.primitives.push_back(std::move(p));
  return model;
}

TEST(ReceiverLights, SitOutsideTheAirframeAndFlashOnSchedule) {
  const std::vector<ReceiverLight> lights = ReceiverLightsOf(Box());
  ASSERT_EQ(lights.size(), 7u);
  const auto named = [&](const std::string& name) {
    for (const ReceiverLight& l : lights) {
      if (l.name == name) return l;
    }
    ADD_FAILURE() << name;
    return ReceiverLight{};
  };
  const ReceiverLight left = named("position_left_red"), right = named("position_right_green");
  EXPECT_NEAR(left.position_in_receiver.y(), 2.0 + left.radius_m, 1e-12);
  EXPECT_NEAR(right.position_in_receiver.y(), -2.0 - right.radius_m, 1e-12);
  EXPECT_NEAR(named("position_tail_white").position_in_receiver.x(), -1.0 - 0.04, 1e-12);
  EXPECT_NEAR(named("beacon_top_red").position_in_receiver.z(), 0.5 + 0.04, 1e-12);
  EXPECT_NEAR(named("beacon_bottom_red").position_in_receiver.z(), -0.5 - 0.04, 1e-12);
  EXPECT_GT(left.color.x(), 5.0 * left.color.y());    // red
  EXPECT_GT(right.color.y(), 5.0 * right.color.x());  // green
  for (const ReceiverLight& l : lights) {
    EXPECT_NEAR(l.color.dot(Eigen::Vector3d(0.2126, 0.7152, 0.0722)), 1.0, 1e-12) << l.name;
    if (l.period_s == 0.0) continue;
    // 400 cd effective (Blondel-Rey), once a second.
    EXPECT_NEAR(l.intensity_cd * l.on_s / (0.2 + l.on_s), 400.0, 1e-9) << l.name;
    EXPECT_TRUE(l.OnAt(l.phase_s + 0.5 * l.on_s)) << l.name;
    EXPECT_TRUE(l.OnAt(l.phase_s + 3.0 + 0.5 * l.on_s)) << l.name;
    EXPECT_FALSE(l.OnAt(l.phase_s + 1.5 * l.on_s)) << l.name;
    EXPECT_FALSE(l.OnAt(l.phase_s - 0.5 * l.on_s)) << l.name;
  }
  EXPECT_TRUE(left.OnAt(0.3));  // steady
  // intensity / (pi r^2) cd/m^2 in render units.
  const Eigen::Vector3d radiance = left.Radiance(2.0);
  EXPECT_NEAR(Eigen::Vector3d(0.2126, 0.7152, 0.0722).dot(radiance),
              40.0 / (kPi * 0.04 * 0.04) * kUnitsPerLux * kPi * 2.0, 1e-9);
}

// A light's sphere rendered in view: its pixels at its radiance, their
// centroid where its centre projects.
TEST(ReceiverLights, ARenderedLightIsWhereItProjectsAtItsRadiance) {
  VulkanContext context{VulkanContextOptions{}};
  const StereoRig rig = LoadRig(SourcePath("scenes/rig.json"));
  const Intrinsics& k = rig.left.intrinsics;
  SceneRendererOptions options;
  options.background = NightOver(BackgroundKind::kTerrain, 0.0);
  SceneRenderer renderer(context, k.width_px, k.height_px, options);
  ReceiverLight light;
  light.name = "test";
  light.radius_m = 0.5;  // 8 px across at the contact position
  light.intensity_cd = 400.0;
  light.color =
      Eigen::Vector3d(0.5, 1.0, 1.5) / Eigen::Vector3d(0.2126, 0.7152, 0.0722).dot(Eigen::Vector3d(0.5, 1.0, 1.5));
  Eigen::Isometry3d tanker_from_light = Eigen::Isometry3d::Identity();
  tanker_from_light.translation() = rig.contact_position_m + Eigen::Vector3d(0.3, 1.1, -0.4);
  const std::vector<RenderItem> items = {
      {renderer.AddModel(LightSphereModel(light, kNightRenderScale)), tanker_from_light, 7.0f}};
  const LinearImage image =
      renderer.RenderColor(rig.left, rig.near_m, items, PlanMsaa(4, context.info().color_sample_counts));
  const GroundTruthImage truth = renderer.RenderGroundTruth(rig.left, rig.near_m, items);
  const Eigen::Vector3d radiance = light.Radiance(kNightRenderScale);
  double weight = 0.0;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  size_t inside = 0;
  for (int v = 0; v < k.height_px; ++v) {
    for (int u = 0; u < k.width_px; ++u) {
      const size_t i = static_cast<size_t>(v) * k.width_px + u;
      const double g = image.rgb[3 * i + 1];
      weight += g;
      centroid += g * Eigen::Vector2d(u, v);
      // Pixels whose neighbours are all the light too are wholly covered.
      bool interior = truth.object_id[i] == 7;
      for (int dv = -1; dv <= 1 && interior; ++dv) {
        for (int du = -1; du <= 1 && interior; ++du) interior = truth.object_id[i + dv * k.width_px + du] == 7;
      }
      if (!interior) continue;
      ++inside;
      for (int c = 0; c < 3; ++c) ASSERT_NEAR(image.rgb[3 * i + c], radiance[c], 2e-3 * radiance[c]) << u << " " << v;
    }
  }
  EXPECT_GT(inside, 10u);
  const Eigen::Vector3d c = rig.left.tanker_from_camera.inverse() * tanker_from_light.translation();
  const Eigen::Vector2d projected(k.fx_px * c.x() / c.z() + k.cx_px, k.fy_px * c.y() / c.z() + k.cy_px);
  EXPECT_LT((centroid / weight - projected).norm(), 0.1);
}

TEST(Floodlight, GivesItsIlluminanceAtTheAimAndFallsOffItsAxis) {
  const StereoRig rig = LoadRig(SourcePath("scenes/rig.json"));
  FloodlightOptions options;
  options.illuminance_lx = 80.0;
  options.beam_sigma_deg = 8.0;
  const Eigen::Vector3d near = rig.contact_position_m, far = rig.contact_position_m + Eigen::Vector3d(-50, 0, -10);
  const Floodlight f = MakeFloodlight(options, rig, {far, near});
  const Eigen::Vector3d to_light = (f.position_in_tanker - near).normalized();
  EXPECT_NEAR(f.IlluminanceAt(near, to_light), 80.0, 1e-9);
  EXPECT_NEAR(f.IlluminanceAt(near, (to_light + Eigen::Vector3d(0.3, 0.2, 0.1)).normalized()),
              80.0 * to_light.dot((to_light + Eigen::Vector3d(0.3, 0.2, 0.1)).normalized()), 1e-9);
  EXPECT_EQ(f.IlluminanceAt(near, -to_light), 0.0);  // facing away
  // One sigma off the axis at the same distance: exp(-1/2).
  const double d = (near - f.position_in_tanker).norm();
  const Eigen::Vector3d side = f.axis_in_tanker.cross(Eigen::Vector3d::UnitZ()).normalized();
  const double a = options.beam_sigma_deg * kPi / 180.0;
  const Eigen::Vector3d off = f.position_in_tanker + d * (std::cos(a) * f.axis_in_tanker + std::sin(a) * side);
  EXPECT_NEAR(f.IlluminanceAt(off, (f.position_in_tanker - off).normalized()), 80.0 * std::exp(-0.5), 1e-6);
  options.illuminance_lx = 0.0;
  EXPECT_THROW(MakeFloodlight(options, rig, {near}), Error);
}

// A white plate at the contact position on a moonless night, lit by the
// floodlight alone: each pixel albedo x E(point, normal) in render units.
TEST(Floodlight, AWhitePlateIsLitByTheInverseSquareLaw) {
  VulkanContext context{VulkanContextOptions{}};
  const StereoRig rig = LoadRig(SourcePath("scenes/rig.json"));
  const Intrinsics& k = rig.left.intrinsics;
  SceneRendererOptions options;
  options.background = NightOver(BackgroundKind::kTerrain, 0.0);
  FloodlightOptions flood;
  flood.illuminance_lx = 60.0;
  flood.beam_sigma_deg = 4.0;  // the plate spans about 2 sigma
  options.floodlight = MakeFloodlight(flood, rig, {rig.contact_position_m});
  SceneRenderer renderer(context, k.width_px, k.height_px, options);
  Primitive plate;
  for (const auto& [x, y] :
       {std::pair{-3.0f, -3.0f}, std::pair{3.0f, -3.0f}, std::pair{3.0f, 3.0f}, std::pair{-3.0f, 3.0f}}) {
    plate.vertices.push_back(Vertex{{x, y, 0.0f}, {0.0f, 0.0f, 1.0f}, {0.0f, 0.0f}});
  }
  plate.indices = {0, 1, 2, 0, 2, 3};
  SceneModel model;
  model.primitives.push_back(std::move(plate));
  Eigen::Isometry3d tanker_from_plate = Eigen::Isometry3d::Identity();
  tanker_from_plate.translation() = rig.contact_position_m;
  tanker_from_plate.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const std::vector<RenderItem> items = {{renderer.AddModel(model), tanker_from_plate, 1.0f}};
  const LinearImage image =
      renderer.RenderColor(rig.left, rig.near_m, items, PlanMsaa(1, context.info().color_sample_counts));
  const GroundTruthImage truth = renderer.RenderGroundTruth(rig.left, rig.near_m, items);
  const Eigen::Vector3d normal = tanker_from_plate.linear() * Eigen::Vector3d::UnitZ();
  size_t pixels = 0;
  double brightest = 0.0, dimmest = 1e9;
  for (int v = 0; v < k.height_px; ++v) {
    for (int u = 0; u < k.width_px; ++u) {
      const size_t i = static_cast<size_t>(v) * k.width_px + u;
      if (truth.object_id[i] != 1) continue;
      const double z = truth.depth_m[i];
      const Eigen::Vector3d p_cam((u - k.cx_px) / k.fx_px * z, (v - k.cy_px) / k.fy_px * z, z);
      const double expected = options.floodlight->IlluminanceAt(rig.left.tanker_from_camera * p_cam, normal) *
                              kUnitsPerLux * kNightRenderScale;
      // The sampled point is within a pixel of the plate point the depth gives.
      ASSERT_NEAR(image.rgb[3 * i + 1], expected, 3e-3 * expected + 1e-4) << u << " " << v;
      ++pixels;
      brightest = std::max(brightest, expected);
      dimmest = std::min(dimmest, expected);
    }
  }
  EXPECT_GT(pixels, 1000u);
  EXPECT_GT(brightest, 3.0 * dimmest);  // the beam's edge is on the plate
}

TEST(Night, ManifestRecordsTheNightItsLightsAndTheExposureOnlyWhenOn) {
  TempDir dir("night-manifest");
  const std::filesystem::path path = dir / "path.csv";
  WriteFileAtomic(path, "time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg\n0.0,-60.0,0.0,-20.0,0.0,0.0,0.0\n");
  for (bool on : {false, true}) {
    RenderJobOptions o;
    o.output = dir / (on ? "on" : "off");
    o.rig = SourcePath("scenes/rig.json");
    o.receiver_model = SourcePath("scenes/c12.glb");
    o.tanker_model = SourcePath("scenes/kc46.glb");
    o.flight_path = path;
    o.progress = false;
    o.msaa = 1;
    o.depth = true;
    o.background.kind = BackgroundKind::kSky;
    if (on) {
      o.background.daylight = DaylightOptions{};
      o.background.night = NightOptions{0.05};
      o.exposure_ev = 11.0;
      o.receiver_lights = true;
      o.floodlight = FloodlightOptions{};
    }
    RenderFlightPathJob(o);
    const nlohmann::json frames = ReadJsonFile(o.output / "manifest.json").at("frames");
    EXPECT_EQ(frames.at("background").contains("daylight"), on);
    for (const char* key : {"camera_exposure", "receiver_lights", "floodlight"}) EXPECT_EQ(frames.contains(key), on);
    if (!on) continue;
    EXPECT_EQ(frames.at("background").at("daylight").at("night").at("moonlight_lx").get<double>(), 0.05);
    EXPECT_EQ(frames.at("camera_exposure").at("factor").get<double>(), 0.5);  // 2^11 / 4096
    EXPECT_EQ(frames.at("receiver_lights").at("lights").size(), 7u);
    EXPECT_NEAR(
        frames.at("floodlight").at("intensity_cd").get<double>(),
        50.0 * (Eigen::Vector3d(-60.0, 0.0, -20.0) - 0.5 * (LoadRig(o.rig).left.tanker_from_camera.translation() +
                                                            LoadRig(o.rig).right.tanker_from_camera.translation()))
                   .squaredNorm(),
        1e-6);
  }
}

}  // namespace
}  // namespace aar
