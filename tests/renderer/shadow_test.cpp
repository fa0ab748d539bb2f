// The sun's shadows (scene.frag's AAR_SHADOWS variants, shadow_map.h,
// sun_camera.h; docs/rendering.md, "Shadows"): the sun camera's geometry, a
// plate's shadow on the ground plate below it where the sun's rays put it,
// the sun's light unchanged outside the shadow, and the manifest's record.

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "../test_support.h"
#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/renderer/background.h"
#include "aar/renderer/msaa.h"
#include "aar/renderer/scene_model.h"
#include "aar/renderer/scene_renderer.h"
#include "aar/renderer/stereo_render_job.h"
#include "aar/renderer/sun_camera.h"
#include "aar/renderer/vulkan_context.h"
#include "aar/rig.h"

namespace aar {
namespace {

using test::SourcePath;
using test::TempDir;

TEST(SunCamera, LooksFromTheSunAtTheSphereAndFramesIt) {
  const Eigen::Vector3d sun = Eigen::Vector3d(0.3, -0.5, 0.81).normalized();
  const Eigen::Vector3d centre(-47.7, 0.0, -18.9);
  const double radius = 9.0;
  const Camera camera = SunCamera(sun, centre, radius, 1024, 768);
  const Eigen::Matrix3d r = camera.tanker_from_camera.linear();
  EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
  EXPECT_LT((r.col(2) + sun).norm(), 1e-12) << "the optical axis points away from the sun";
  EXPECT_NEAR((camera.tanker_from_camera.translation() - centre).norm(), kSunCameraDistanceM, 1e-6);
  const Eigen::Vector2d at_centre = *camera.intrinsics.Project(camera.tanker_from_camera.inverse() * centre);
  EXPECT_NEAR(at_centre.x(), 511.5, 1e-6);
  EXPECT_NEAR(at_centre.y(), 383.5, 1e-6);
  // The sphere's outline (the tangent cone's circle) 2 px inside the shorter side.
  const double d = kSunCameraDistanceM, tangent = std::sqrt(d * d - radius * radius);
  const Eigen::Vector3d rim_in_camera(radius * tangent / d, 0.0, tangent * tangent / d);
  const Eigen::Vector2d rim = *camera.intrinsics.Project(rim_in_camera);
  EXPECT_NEAR(rim.x() - 511.5, 384.0 - 2.0, 1e-6);
  // Straight overhead the x axis falls back to the tanker's y.
  const Camera overhead = SunCamera(Eigen::Vector3d::UnitZ(), centre, radius, 64, 64);
  EXPECT_LT((overhead.tanker_from_camera.linear().col(0) - Eigen::Vector3d::UnitY()).norm(), 1e-12);
  EXPECT_THROW(SunCamera(2.0 * sun, centre, radius, 64, 64), Error);
  EXPECT_THROW(SunCamera(sun, centre, 0.0, 64, 64), Error);
}

// A white horizontal square of side `side_m` about the body origin, normal +z.
SceneModel Plate(double side_m) {
  Primitive p;
  const float h = static_cast<float>(side_m / 2.0);
  for (const auto& [x, y] : {std::pair{-h, -h}, std::pair{h, -h}, std::pair{h, h}, std::pair{-h, h}}) {
    p.vertices.push_back(Vertex{{x, y, 0.0f}, {0.0f, 0.0f, 1.0f}, {0.0f, 0.0f}});
  }
  p.indices = {0, 1, 2, 0, 2, 3};
  SceneModel model;
  model.primitives.push_back(std::move(p));
  return model;
}

struct PlateScene {
  StereoRig rig;
  Eigen::Vector3d ground_centre, caster_centre, sun;
  LinearImage lit, shadowed;
  GroundTruthImage truth;
};

constexpr double kGroundSideM = 8.0, kCasterSideM = 2.0, kCasterHeightM = 3.0;

// The ground plate (the shadowed object, id 1) at the rig's contact position
// and a smaller plate (id 2) above it, seen by the left camera with one
// sample per pixel, with and without shadows.
PlateScene RenderPlates() {
  PlateScene s;
  s.rig = LoadRig(SourcePath("scenes/rig.json"));
  s.ground_centre = s.rig.contact_position_m;
  s.caster_centre = s.ground_centre + Eigen::Vector3d(0.0, 0.0, kCasterHeightM);
  s.sun = LevelFromTanker(BackgroundOptions{}).transpose() * SunInLevel(BackgroundOptions{});  // as the renderer's
  VulkanContext context{VulkanContextOptions{}};
  const Intrinsics& k = s.rig.left.intrinsics;
  const MsaaPlan x1 = PlanMsaa(1, context.info().color_sample_counts);
  for (bool shadows : {false, true}) {
    SceneRendererOptions options;
    options.shadows = shadows;
    SceneRenderer renderer(context, k.width_px, k.height_px, options);
    Eigen::Isometry3d tanker_from_ground = Eigen::Isometry3d::Identity(), tanker_from_caster = tanker_from_ground;
    tanker_from_ground.translation() = s.ground_centre;
    tanker_from_caster.translation() = s.caster_centre;
    const std::vector<RenderItem> items = {{renderer.AddModel(Plate(kGroundSideM)), tanker_from_ground, 1.0f},
                                           {renderer.AddModel(Plate(kCasterSideM)), tanker_from_caster, 2.0f}};
    (shadows ? s.shadowed : s.lit) = renderer.RenderColor(s.rig.left, s.rig.near_m, items, x1);
    if (!shadows) s.truth = renderer.RenderGroundTruth(s.rig.left, s.rig.near_m, items);
  }
  return s;
}

// Where the ray through pixel (u, v) meets the ground plate's plane.
Eigen::Vector3d OnGround(const PlateScene& s, int u, int v) {
  const Intrinsics& k = s.rig.left.intrinsics;
  const Eigen::Vector3d ray =
      s.rig.left.tanker_from_camera.linear() * Eigen::Vector3d((u - k.cx_px) / k.fx_px, (v - k.cy_px) / k.fy_px, 1.0);
  const Eigen::Vector3d origin = s.rig.left.tanker_from_camera.translation();
  return origin + ray * ((s.ground_centre.z() - origin.z()) / ray.z());
}

// The ground plate's pixels that the camera sees (not behind the caster) are
// lit by the sun where the caster's shadow, the caster moved along the sun's
// rays onto the ground, does not fall, and by the sky alone where it does;
// outside the shadow the image is that of the renderer without shadows, to
// the bit; the partly lit pixels lie within half a pixel of the geometry's
// edge.
TEST(Shadows, ThePlatesShadowFallsWhereTheSunsRaysPutIt) {
  const PlateScene s = RenderPlates();
  const Eigen::Vector2d shift = -kCasterHeightM * s.sun.head<2>() / s.sun.z();
  const Eigen::Vector2d shadow_centre = s.caster_centre.head<2>() + shift;
  const float sky = 0.35f, sunlit = sky + 0.75f * static_cast<float>(s.sun.z());  // scene.frag, white, n = +z
  const Intrinsics& k = s.rig.left.intrinsics;
  size_t inside = 0, outside = 0, edge = 0;
  double worst_edge_px = 0.0;
  for (int v = 0; v < k.height_px; ++v) {
    for (int u = 0; u < k.width_px; ++u) {
      const size_t i = static_cast<size_t>(v) * k.width_px + u;
      if (s.truth.object_id[i] != 1) continue;
      const Eigen::Vector2d p = OnGround(s, u, v).head<2>();
      const Eigen::Vector2d in_shadow = (p - shadow_centre).cwiseAbs();
      // Metres per pixel on the ground here, along the worse direction.
      const double px_m = (OnGround(s, u + 1, v + 1).head<2>() - OnGround(s, u, v).head<2>()).norm();
      const double outside_m = in_shadow.maxCoeff() - kCasterSideM / 2.0;  // > 0 outside the shadow
      const float value = s.shadowed.rgb[3 * i];
      if (outside_m < -2.0 * px_m) {
        ++inside;
        EXPECT_NEAR(value, sky, 1e-3) << "pixel " << u << "," << v << " should be in shadow";
      } else if (outside_m > 2.0 * px_m) {
        ++outside;
        EXPECT_NEAR(value, sunlit, 1e-3) << "pixel " << u << "," << v << " should be in the sun";
        EXPECT_EQ(value, s.lit.rgb[3 * i]);
      }
      // Partly lit (the four texels' bilinear share, a texel wide): on the
      // geometry's edge.
      if (value > sky + 0.01f && value < sunlit - 0.01f) {
        ++edge;
        worst_edge_px = std::max(worst_edge_px, std::abs(outside_m) / px_m);
      }
    }
  }
  EXPECT_GT(inside, 200u);
  EXPECT_GT(outside, 2000u);
  EXPECT_GT(edge, 0u);
  EXPECT_LT(worst_edge_px, 0.5);
}

TEST(Shadows, TheManifestRecordsThemOnlyWhenOn) {
  TempDir dir;
  for (bool shadows : {false, true}) {
    RenderJobOptions o;
    o.output = dir / (shadows ? "on" : "off");
    o.rig = SourcePath("scenes/rig.json");
    o.receiver_model = SourcePath("scenes/c12.glb");
    o.tanker_model = SourcePath("scenes/kc46.glb");
    o.flight_path = SourcePath("flightpaths/conops.csv");
    o.selection = ParseFrameSelection("600:601", "");
    o.msaa = 1;
    o.shadows = shadows;
    o.progress = false;
    SunOptions sun;
    sun.azimuth_deg = 0.0;  // ahead, low: the tanker's shadow falls on the receiver
    sun.elevation_deg = 25.0;
    o.background.sun = sun;
    RenderFlightPathJob(o);
    const nlohmann::json frames = nlohmann::json::parse(ReadFileBytes(o.output / kManifestName)).at("frames");
    EXPECT_EQ(frames.contains("shadows"), shadows);
    if (shadows) {
      EXPECT_EQ(frames.at("shadows").at("map_texels"), nlohmann::json::array({1024, 768}));
    }
  }
  EXPECT_NE(ReadFileBytes(dir / "off" / kFramesDir / "000600_left.png"),
            ReadFileBytes(dir / "on" / kFramesDir / "000600_left.png"));
}

}  // namespace
}  // namespace aar
