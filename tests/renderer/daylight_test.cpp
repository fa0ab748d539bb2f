// Daylight (--daylight; daylight.h, docs/rendering.md "Daylight"): the air
// mass, pressure and Rayleigh depth against published values, Preetham's sky
// and the sun's colour following the sun, the background shader's sky and
// ground against the CPU model, the sun's disc where the sun is and as large
// as it is, a white plate lit by the sun and sky the model gives, and the
// manifest's record.

#include "aar/renderer/daylight.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "../test_support.h"
#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/json_file.h"
#include "aar/renderer/background.h"
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

TEST(Daylight, AirMassPressureAndRayleighDepthMatchPublishedValues) {
  EXPECT_NEAR(RelativeAirMass(0.0), 1.0, 1e-3);
  for (double z = 0.0; z <= 60.0; z += 5.0) {  // a plane-parallel atmosphere's secant, where it holds
    EXPECT_NEAR(RelativeAirMass(z) * std::cos(z * kDeg), 1.0, 3e-3) << z << " deg";
  }
  EXPECT_NEAR(RelativeAirMass(90.0), 38.0868, 0.01 * 38.0868);  // Kasten and Young 1989, at the horizon
  // US Standard Atmosphere 1976: 41.105, 22.632 and 12.111 kPa of 101.325.
  EXPECT_NEAR(PressureRatio(7000.0), 41.105 / 101.325, 2e-3);
  EXPECT_NEAR(PressureRatio(11000.0), 22.632 / 101.325, 2e-3);
  EXPECT_NEAR(PressureRatio(15000.0), 12.111 / 101.325, 2e-3);
  // Rayleigh's vertical depth at 550 nm from sea level: 0.0973 (Bodhaine et
  // al. 1999). Turbidity 0.99523 has no aerosols (beta 0); 100 km up only ozone is left.
  const double no_aerosol = 0.04586 / 0.04608;
  const double rayleigh = VerticalOpticalDepth(0.0, no_aerosol, 1500.0)[1] - VerticalOpticalDepth(1e5, 3.0, 1500.0)[1];
  EXPECT_NEAR(rayleigh, 0.0973, 0.05 * 0.0973);
}

TEST(Daylight, SkyAndSunFollowTheSun) {
  const Eigen::Vector3d high(0.0, -std::cos(60 * kDeg), std::sin(60 * kDeg));
  const Eigen::Vector3d low(-std::cos(5 * kDeg), 0.0, std::sin(5 * kDeg));
  const PreethamSky sky_high = MakePreethamSky(3.0, high), sky_low = MakePreethamSky(3.0, low);
  EXPECT_NEAR(sky_high.Yxy(Eigen::Vector3d::UnitZ())[0], PreethamSky::ZenithLuminance(3.0, 30 * kDeg), 1e-12);
  EXPECT_GT(sky_high.zenith[0], 2.0 * sky_low.zenith[0]);  // the zenith darkens as the sun sets
  // Near the sun brighter than away from it; at a low sun the horizon under it is redder.
  const Eigen::Vector3d near_low = (low + Eigen::Vector3d(0.0, 0.1, 0.0)).normalized();
  EXPECT_GT(sky_low.Yxy(near_low)[0], 3.0 * sky_low.Yxy(-near_low + Eigen::Vector3d(0, 0, 0.2))[0]);
  const Eigen::Vector3d under_sun = sky_low.Radiance(Eigen::Vector3d(-1.0, 0.0, 0.0));
  const Eigen::Vector3d under_high = sky_high.Radiance(Eigen::Vector3d(0.0, -1.0, 0.0));
  EXPECT_GT(under_sun[0] / under_sun[2], 2.0 * under_high[0] / under_high[2]);
  // The direct sun: redder and dimmer low, dimmer at the ground than at 7 km.
  const Eigen::Vector3d t55 = SunTransmittance(55.0, 7000.0, 3.0, 1500.0);
  const Eigen::Vector3d t5 = SunTransmittance(5.0, 7000.0, 3.0, 1500.0);
  EXPECT_GT(t5[0] / t5[2], 1.5 * t55[0] / t55[2]);
  EXPECT_LT(t5.maxCoeff(), t55.minCoeff());
  EXPECT_LT((SunTransmittance(55.0, 0.0, 3.0, 1500.0) - t55).maxCoeff(), 0.0);
  EXPECT_THROW(MakePreethamSky(12.0, high), Error);
  BackgroundOptions flat;
  flat.daylight = DaylightOptions{};
  EXPECT_THROW(flat.Check(), Error);  // the flat sky has no daylight
}

BackgroundOptions LowSunAft() {
  BackgroundOptions bg;
  bg.kind = BackgroundKind::kSky;
  bg.tanker_pitch_deg = 20.0;  // the horizon and the sky come into view
  bg.sun = SunOptions{180.0, 8.0, "test"};
  bg.daylight = DaylightOptions{};
  return bg;
}

// The background pass against daylight.cpp's model: sky pixels are Preetham's
// sky in their ray's direction, ground pixels the plain ground lit and hazed;
// the sun's disc, aft and 8 deg up, centred where the sun projects and as
// large as the sun.
TEST(Daylight, TheBackgroundIsTheModelAndTheSunsDiscIsWhereTheSunIs) {
  VulkanContext context{VulkanContextOptions{}};
  const StereoRig rig = LoadRig(SourcePath("scenes/rig.json"));
  const Intrinsics& k = rig.left.intrinsics;
  SceneRendererOptions options;
  options.background = LowSunAft();
  SceneRenderer renderer(context, k.width_px, k.height_px, options);
  const LinearImage image =
      renderer.RenderColor(rig.left, rig.near_m, {}, PlanMsaa(1, context.info().color_sample_counts));
  const BackgroundOptions& bg = options.background;
  const Daylight daylight = ComputeDaylight(bg, {kPlainGroundAlbedo[0], kPlainGroundAlbedo[1], kPlainGroundAlbedo[2]});
  const Eigen::Matrix3d level_from_pixel = LevelFromPixel(rig.left, bg);
  const Eigen::Vector3d sun = SunInLevel(bg);
  ASSERT_NEAR(k.fx_px, k.fy_px, 1e-9);
  const double disc_px = kSunAngularRadiusRad * k.fx_px;
  size_t sky = 0, ground = 0;
  double worst = 0.0, disc_area = 0.0;
  Eigen::Vector2d disc_centroid = Eigen::Vector2d::Zero();
  for (int v = 0; v < k.height_px; v += 1) {
    for (int u = 0; u < k.width_px; u += 1) {
      const Eigen::Vector3d ray = (level_from_pixel * Eigen::Vector3d(u, v, 1.0)).normalized();
      const size_t i = static_cast<size_t>(v) * k.width_px + u;
      const Eigen::Vector3d rendered(image.rgb[3 * i], image.rgb[3 * i + 1], image.rgb[3 * i + 2]);
      const double from_sun = std::acos(std::min(ray.dot(sun), 1.0));
      const bool hits = SphereHitParameter(ray, CameraAboveGround(rig.left, bg).z()).has_value();
      Eigen::Vector3d model;
      if (hits) {
        model = BelowHorizonRadiance(bg, daylight, ray,
                                     {kPlainGroundAlbedo[0], kPlainGroundAlbedo[1], kPlainGroundAlbedo[2]});
        ++ground;
      } else {
        model = daylight.sky.Radiance(ray);
        ++sky;
        if (from_sun < kSunAngularRadiusRad + 2.0 / k.fx_px) {
          const double coverage = (rendered - model)[1] / daylight.sun_disc[1];
          disc_area += coverage;
          disc_centroid += coverage * Eigen::Vector2d(u, v);
          continue;
        }
      }
      if (u % 7 != 0 || v % 7 != 0) continue;
      // Half floats (11 bits) and the shader's float maths.
      worst = std::max(worst, ((rendered - model).cwiseAbs() - 2e-3 * model).maxCoeff());
    }
  }
  EXPECT_GT(sky, 100000u);
  EXPECT_GT(ground, 100000u);
  EXPECT_LT(worst, 2e-4);
  // A small circle of the sky at angle theta off the optical axis projects
  // to an ellipse of semi-axes r f / cos^2 theta and r f / cos theta.
  const Eigen::Vector3d sun_in_camera =
      rig.left.tanker_from_camera.linear().transpose() * LevelFromTanker(bg).transpose() * sun;
  const double cos_theta = sun_in_camera.z();
  const double area = kPi * disc_px * disc_px / std::pow(cos_theta, 3.0);
  EXPECT_LT(cos_theta, 0.97);  // off axis: the test would not tell the ellipse from the circle on it
  EXPECT_NEAR(disc_area, area, 0.03 * area);
  const Eigen::Vector2d projected(k.fx_px * sun_in_camera.x() / sun_in_camera.z() + k.cx_px,
                                  k.fy_px * sun_in_camera.y() / sun_in_camera.z() + k.cy_px);
  ASSERT_GT(disc_area, 0.0);
  EXPECT_LT((disc_centroid / disc_area - projected).norm(), 0.1);
}

// A white horizontal plate at the contact position, seen from above: the
// sky's light from above plus the sun's at the tanker times the sun's height.
TEST(Daylight, AWhitePlateIsLitByTheSunAndSkyTheModelGives) {
  VulkanContext context{VulkanContextOptions{}};
  const StereoRig rig = LoadRig(SourcePath("scenes/rig.json"));
  const Intrinsics& k = rig.left.intrinsics;
  SceneRendererOptions options;
  options.background.kind = BackgroundKind::kTerrain;
  options.background.sun = SunOptions{30.0, 40.0, "test"};
  options.background.daylight = DaylightOptions{4.0};
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
  const std::vector<RenderItem> items = {{renderer.AddModel(model), tanker_from_plate, 1.0f}};
  const LinearImage image =
      renderer.RenderColor(rig.left, rig.near_m, items, PlanMsaa(1, context.info().color_sample_counts));
  const GroundTruthImage truth = renderer.RenderGroundTruth(rig.left, rig.near_m, items);

  // The terrain's mean albedo, as the renderer takes it.
  const TextureMips terrain = TerrainTexture(options.background.seed);
  Eigen::Vector3d albedo;
  for (int c = 0; c < 3; ++c) albedo[c] = SrgbToLinear(terrain.levels.back()[c] / 255.0f);
  const Daylight d = ComputeDaylight(options.background, albedo);
  const Eigen::Vector3d expected = d.sky_from_above + d.sun_at_tanker * SunInLevel(options.background).z();
  size_t pixels = 0;
  for (size_t i = 0; i < truth.object_id.size(); ++i) {
    if (truth.object_id[i] != 1) continue;
    ++pixels;
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(image.rgb[3 * i + c], expected[c], 2e-3 * expected[c]) << i;
  }
  EXPECT_GT(pixels, 1000u);
  // Not the fixed light: 0.35 + 0.75 sun z.
  EXPECT_GT(std::abs(expected[1] - (0.35 + 0.75 * SunInLevel(options.background).z())), 0.05);
}

TEST(Daylight, ManifestRecordsItOnlyWhenOn) {
  TempDir dir("daylight-manifest");
  const std::filesystem::path path = dir / "path.csv";
  WriteFileAtomic(path, "time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg\n0.0,200.0,0.0,0.0,0.0,0.0,0.0\n");
  for (bool on : {false, true}) {
    RenderJobOptions o;
    o.output = dir / (on ? "on" : "off");
    o.rig = SourcePath("scenes/rig.json");
    o.receiver_model = SourcePath("scenes/c12.glb");
    o.tanker_model = SourcePath("scenes/kc46.glb");
    o.flight_path = path;
    o.progress = false;
    o.msaa = 1;
    o.background.kind = BackgroundKind::kClouds;
    if (on) o.background.daylight = DaylightOptions{2.5};
    RenderFlightPathJob(o);
    const nlohmann::json manifest = ReadJsonFile(o.output / "manifest.json");
    const nlohmann::json& background = manifest.at("frames").at("background");
    ASSERT_EQ(background.contains("daylight"), on);
    if (on) {
      EXPECT_EQ(background.at("daylight").at("turbidity").get<double>(), 2.5);
      // At the deck's top the sun has crossed more air than at the tanker.
      const auto at_tanker = background.at("daylight").at("sun_transmittance_at_tanker").get<std::vector<double>>();
      const auto at_deck = background.at("daylight").at("sun_transmittance_at_surface").get<std::vector<double>>();
      for (int c = 0; c < 3; ++c) EXPECT_LT(at_deck[c], at_tanker[c]);
    }
  }
}

}  // namespace
}  // namespace aar
