// Physically based shading (scene.frag with AAR_PBR, docs/rendering.md
// "Physically based shading"): the sun's highlight on a polished sphere where
// the law of reflection puts it, a rough dielectric's light against the matte
// model's, the models' materials, and the manifest's record.

#include "aar/renderer/shading.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "../test_support.h"
#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/renderer/background.h"
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

// A UV sphere of `radius_m` about the body origin, outward normals, one
// material (base colour white, untextured).
SceneModel Sphere(double radius_m, float metallic, float roughness) {
  constexpr int kRings = 96, kSegments = 192;
  Primitive p;
  for (int i = 0; i <= kRings; ++i) {
    const double theta = M_PI * i / kRings;  // from +z
    for (int j = 0; j <= kSegments; ++j) {
      const double phi = 2.0 * M_PI * j / kSegments;
      const Eigen::Vector3d n(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
      Vertex v{};
      for (int k = 0; k < 3; ++k) {
        v.position[k] = static_cast<float>(radius_m * n[k]);
        v.normal[k] = static_cast<float>(n[k]);
      }
      p.vertices.push_back(v);
    }
  }
  for (int i = 0; i < kRings; ++i) {
    for (int j = 0; j < kSegments; ++j) {
      const uint32_t a = i * (kSegments + 1) + j, b = a + kSegments + 1;
      for (uint32_t index : {a, b, a + 1, a + 1, b, b + 1}) p.indices.push_back(index);
    }
  }
  p.metallic = metallic;
  p.roughness = roughness;
  SceneModel model;
  model.primitives.push_back(std::move(p));
  return model;
}

struct SphereView {
  LinearImage image;
  Eigen::Vector3d centre;  // tanker frame
  StereoRig rig;
};

SphereView RenderSphere(Shading shading, float metallic, float roughness) {
  VulkanContext context{VulkanContextOptions{}};
  SphereView view;
  view.rig = LoadRig(SourcePath("scenes/rig.json"));
  view.centre = view.rig.contact_position_m;
  SceneRendererOptions options;
  options.shading = shading;
  const Intrinsics& k = view.rig.left.intrinsics;
  SceneRenderer renderer(context, k.width_px, k.height_px, options);
  Eigen::Isometry3d tanker_from_sphere = Eigen::Isometry3d::Identity();
  tanker_from_sphere.translation() = view.centre;
  const std::vector<RenderItem> items = {
      {renderer.AddModel(Sphere(1.5, metallic, roughness)), tanker_from_sphere, 1.0f}};
  view.image =
      renderer.RenderColor(view.rig.left, view.rig.near_m, items, PlanMsaa(1, context.info().color_sample_counts));
  return view;
}

// The brightest pixel (sum of the channels) in the image.
Eigen::Vector2d Brightest(const LinearImage& image) {
  size_t best = 0;
  float best_value = -1.0f;
  for (size_t i = 0; i < static_cast<size_t>(image.width) * image.height; ++i) {
    const float value = image.rgb[3 * i] + image.rgb[3 * i + 1] + image.rgb[3 * i + 2];
    if (value > best_value) best_value = value, best = i;
  }
  return {static_cast<double>(best % image.width), static_cast<double>(best / image.width)};
}

// Where a point on the sphere's surface, found by `normal_at` (the unit
// normal the point must have, given the point), projects in the left camera.
template <typename NormalAt>
Eigen::Vector2d ProjectSurfacePoint(const SphereView& view, NormalAt normal_at) {
  Eigen::Vector3d point = view.centre;
  for (int iteration = 0; iteration < 20; ++iteration) point = view.centre + 1.5 * normal_at(point);
  const Eigen::Vector3d in_camera = view.rig.left.tanker_from_camera.inverse() * point;
  return *view.rig.left.intrinsics.Project(in_camera);
}

TEST(Shading, ParsesItsNames) {
  EXPECT_EQ(ParseShading("matte"), Shading::kMatte);
  EXPECT_EQ(ParseShading("pbr"), Shading::kPbr);
  EXPECT_EQ(ToString(Shading::kPbr), "pbr");
  EXPECT_THROW(ParseShading("phong"), Error);
}

// A polished metal sphere reflects the sun where its normal halves the
// angle between the sun and the camera; the matte model's brightest point is
// where the normal faces the light, far from it, so the test tells them apart.
TEST(Shading, TheSunsHighlightIsWhereTheLawOfReflectionPutsIt) {
  const Eigen::Vector3d sun =
      LevelFromTanker(BackgroundOptions{}).transpose() * SunInLevel(BackgroundOptions{});  // as the renderer's
  const SphereView pbr = RenderSphere(Shading::kPbr, 1.0f, 0.1f);
  const Eigen::Vector3d camera = pbr.rig.left.tanker_from_camera.translation();
  const Eigen::Vector2d mirror = ProjectSurfacePoint(
      pbr, [&](const Eigen::Vector3d& p) { return (sun + (camera - p).normalized()).normalized(); });
  // The matte model's light, 0.75 n.sun + 0.35 (0.75 + 0.25 n.z), is largest
  // where n is along 0.75 sun + 0.0875 z (scene.frag).
  const Eigen::Vector3d matte_peak = (0.75 * sun + 0.0875 * Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector2d facing_sun = ProjectSurfacePoint(pbr, [&](const Eigen::Vector3d&) { return matte_peak; });
  ASSERT_GT((mirror - facing_sun).norm(), 8.0) << "the geometry does not separate the two laws";
  const Eigen::Vector2d highlight = Brightest(pbr.image);
  EXPECT_LT((highlight - mirror).norm(), 1.0)
      << "highlight at " << highlight.transpose() << ", the law puts it at " << mirror.transpose();
  // The same sphere matte is brightest where it faces the light (within the
  // facets' and the pixels' rounding: the cosine is flat at its peak).
  const SphereView matte = RenderSphere(Shading::kMatte, 1.0f, 0.1f);
  EXPECT_LT((Brightest(matte.image) - facing_sun).norm(), 4.0);
  EXPECT_GT((Brightest(matte.image) - mirror).norm(), 4.0);
}

// A rough dielectric (roughness 1, metallic 0) keeps the matte model's light
// within what its 4 % reflectance moves: each lit pixel within 4 % (less
// diffuse) and a small specular term of the matte value.
TEST(Shading, ARoughDielectricStaysCloseToMatte) {
  const SphereView pbr = RenderSphere(Shading::kPbr, 0.0f, 1.0f);
  const SphereView matte = RenderSphere(Shading::kMatte, 0.0f, 1.0f);
  size_t lit = 0;
  double worst = 0.0;
  for (size_t i = 0; i < pbr.image.rgb.size(); ++i) {
    if (pbr.image.rgb[i] == matte.image.rgb[i]) continue;  // sky
    ++lit;
    worst = std::max(worst, std::abs(pbr.image.rgb[i] / matte.image.rgb[i] - 1.0));
  }
  EXPECT_GT(lit, 3000u);
  EXPECT_LT(worst, 0.15);
}

TEST(Shading, ModelsCarryTheirMaterials) {
  const SceneModel c12 = LoadSceneModel(SourcePath("scenes/c12.glb"));
  ASSERT_FALSE(c12.primitives.empty());
  EXPECT_FLOAT_EQ(c12.primitives[0].metallic, 0.0f);
  EXPECT_FLOAT_EQ(c12.primitives[0].roughness, 0.35f);
  const SceneModel tube = LoadSceneModel(SourcePath("scenes/kc46_boom_tube.glb"));
  bool metal = false;
  for (const Primitive& p : tube.primitives) metal = metal || p.metallic == 1.0f;
  EXPECT_TRUE(metal) << "the nozzle at the tube's end is bare metal";
}

TEST(Shading, TheManifestRecordsPbrOnly) {
  TempDir dir;
  for (Shading shading : {Shading::kMatte, Shading::kPbr}) {
    RenderJobOptions o;
    o.output = dir / ToString(shading);
    o.rig = SourcePath("scenes/rig.json");
    o.receiver_model = SourcePath("scenes/c12.glb");
    o.tanker_model = SourcePath("scenes/kc46.glb");
    o.flight_path = SourcePath("flightpaths/conops.csv");
    o.selection = ParseFrameSelection("600:601", "");
    o.msaa = 1;
    o.shading = shading;
    o.progress = false;
    RenderFlightPathJob(o);
    const nlohmann::json frames = nlohmann::json::parse(ReadFileBytes(o.output / kManifestName)).at("frames");
    if (shading == Shading::kMatte) {
      EXPECT_FALSE(frames.contains("shading"));
    } else {
      EXPECT_EQ(frames.at("shading"), "pbr");
    }
  }
  EXPECT_NE(ReadFileBytes(dir / "matte" / kFramesDir / "000600_left.png"),
            ReadFileBytes(dir / "pbr" / kFramesDir / "000600_left.png"));
}

}  // namespace
}  // namespace aar
