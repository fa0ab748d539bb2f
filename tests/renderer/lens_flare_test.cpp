// Lens flare's ghosts of the sun (lens_flare.h; docs/rendering.md, "Lens
// flare"): each ghost on the line from the image centre through the sun's
// image at its declared place, its flux the declared fraction of the sun's
// irradiance on the aperture, what falls beyond the image lost, nothing with
// the sun behind the lens, and a rendered frame whose ghost lies where the
// sun's projection puts it.

#include "aar/renderer/lens_flare.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>

#include "../test_support.h"
#include "aar/dataset.h"
#include "aar/file_io.h"
#include "aar/json_file.h"
#include "aar/renderer/background.h"
#include "aar/renderer/stereo_render_job.h"
#include "aar/rig.h"

namespace aar {
namespace {

using test::SourcePath;
using test::TempDir;

constexpr double kPi = 3.14159265358979323846;

Camera RigLeft() { return LoadRig(SourcePath("scenes/rig.json")).left; }

Eigen::Vector3d RayInTanker(const Camera& camera, double u, double v) {
  const Intrinsics& k = camera.intrinsics;
  return (camera.tanker_from_camera.linear() * Eigen::Vector3d((u - k.cx_px) / k.fx_px, (v - k.cy_px) / k.fy_px, 1.0))
      .normalized();
}

struct Measured {
  double flux = 0.0;                                   // sum of radiance x pixel solid angle, channel 0
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();  // of the radiance
};

Measured Measure(const LensFlare& flare, const Intrinsics& k) {
  Measured m;
  double total = 0.0;
  for (int v = 0; v < k.height_px; ++v) {
    for (int u = 0; u < k.width_px; ++u) {
      const double x = (u - k.cx_px) / k.fx_px, y = (v - k.cy_px) / k.fy_px;
      const double solid_angle = std::pow(1.0 + x * x + y * y, -1.5) / (k.fx_px * k.fy_px);
      const double value = flare.image()[(static_cast<size_t>(v) * k.width_px + u) * 3];
      m.flux += value * solid_angle;
      m.centroid += value * Eigen::Vector2d(u, v);
      total += value;
    }
  }
  if (total > 0.0) m.centroid /= total;
  return m;
}

// The sun at pixel (300, 200); one ghost across the centre (position -1),
// one halfway (0.5): their centres on the line, each ghost's flux the
// fraction of pi S cos(alpha), its radiance uniform inside the disc.
TEST(LensFlare, GhostsLieOnTheLineThroughTheCentreAndHoldTheirFlux) {
  const Camera camera = RigLeft();
  const Intrinsics& k = camera.intrinsics;
  const Eigen::Vector3d sun = RayInTanker(camera, 300.0, 200.0);
  const double aperture = (camera.tanker_from_camera.linear().transpose() * sun).z();
  const Eigen::Vector3d light(0.7, 0.6, 0.5);
  const Eigen::Vector2d c(k.cx_px, k.cy_px), s(300.0, 200.0);
  for (const FlareGhost& ghost : {FlareGhost{-1.0, 30.0, 2e-4}, FlareGhost{0.5, 12.0, 5e-5}}) {
    const LensFlare flare(camera, sun, light, {ghost});
    const Eigen::Vector2d expected = c + ghost.position * (s - c);
    ASSERT_EQ(flare.centres_px().size(), 1u);
    EXPECT_NEAR((flare.centres_px()[0] - expected).norm(), 0.0, 1e-9);
    const Measured m = Measure(flare, k);
    const double irradiance = kPi * aperture * light[0];
    EXPECT_NEAR(m.flux, ghost.fraction * irradiance, 1e-4 * ghost.fraction * irradiance);
    EXPECT_NEAR((m.centroid - expected).norm(), 0.0, 0.1);
    // Uniform inside: the pixel at the centre and one 0.7 radius out (the
    // solid angle per pixel changes by < 1 % over the disc, the radiance not).
    const auto at = [&](double u, double v) {
      return flare.image()[(static_cast<size_t>(std::lround(v)) * k.width_px + std::lround(u)) * 3 + 1];
    };
    EXPECT_GT(at(expected.x(), expected.y()), 0.0f);
    EXPECT_EQ(at(expected.x(), expected.y()), at(expected.x() + 0.7 * ghost.radius_px, expected.y()));
    EXPECT_EQ(at(expected.x() + ghost.radius_px + 2.0, expected.y()), 0.0f);
  }
}

// A ghost centred on the image's left edge, on the centres of column 0,
// keeps half its flux and the half-pixel strip of column 0 beyond the
// centres: 0.5 + (2 r x 0.5) / (pi r^2), in a narrow camera (fx 20,000
// px) whose pixels' solid angles are the same across the disc; none at
// all with the sun behind the lens.
TEST(LensFlare, WhatFallsBeyondTheImageIsLostAndNothingComesFromBehind) {
  Camera camera = RigLeft();
  camera.intrinsics.fx_px = camera.intrinsics.fy_px = 20000.0;
  const Intrinsics& k = camera.intrinsics;
  // position 1: the ghost on the sun's own image, here at u = 0.
  const Eigen::Vector3d sun = RayInTanker(camera, 0.0, k.cy_px);
  const double aperture = (camera.tanker_from_camera.linear().transpose() * sun).z();
  const FlareGhost ghost{1.0, 40.0, 1e-4};
  const Measured m = Measure(LensFlare(camera, sun, Eigen::Vector3d::Constant(1.0), {ghost}), k);
  const double whole = ghost.fraction * kPi * aperture;
  const double kept = 0.5 + 1.0 / (kPi * ghost.radius_px);
  EXPECT_NEAR(m.flux / whole, kept, 0.002);
  const LensFlare behind(camera, -camera.tanker_from_camera.linear().col(2), Eigen::Vector3d::Constant(0.75),
                         {FlareGhost{-1.0, 20.0, 1e-3}});
  EXPECT_TRUE(behind.centres_px().empty());
  for (float value : behind.image()) ASSERT_EQ(value, 0.0f);
}

// Rendered: scenes/rig-noisy.json with one ghost across the centre
// (position -0.6, radius 15 px, fraction 1e-4), the sun 5 deg up aft and
// the tanker pitched 20 deg nose down so that it is in view: the frame
// brightens in a disc of the ghost's size centred at c - 0.6 (s - c), s
// where the sun projects.
TEST(LensFlare, ARenderedGhostLiesAcrossTheCentreFromTheSunsDisc) {
  TempDir dir("lens-flare");
  const std::filesystem::path path = dir / "path.csv";
  WriteFileAtomic(path, "time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg\n0.0,200.0,0.0,0.0,0.0,0.0,0.0\n");
  nlohmann::json rig = ReadJsonFile(SourcePath("scenes/rig-noisy.json"));
  rig["sensor"]["flare_ghosts"] = {{{"position", -0.6}, {"radius_px", 15.0}, {"fraction", 1e-4}}};
  const std::filesystem::path flare_rig = dir / "rig-flare.json";
  WriteFileAtomic(flare_rig, rig.dump(2));
  auto render = [&](const std::string& name, const std::filesystem::path& rig_path) {
    RenderJobOptions o;
    o.output = dir / name;
    o.rig = rig_path;
    o.receiver_model = SourcePath("scenes/c12.glb");
    o.tanker_model = SourcePath("scenes/kc46.glb");
    o.flight_path = path;
    o.progress = false;
    o.msaa = 1;
    o.background.kind = BackgroundKind::kSky;
    o.background.tanker_pitch_deg = 20.0;
    o.background.sun = SunOptions{180.0, 5.0, "test"};
    RenderFlightPathJob(o);
    return cv::imread((o.output / ReadSidecar(SidecarPath(o.output, "frame", 0)).files.at("left").path).string(),
                      cv::IMREAD_GRAYSCALE);
  };
  const cv::Mat with = render("with", flare_rig), without = render("without", SourcePath("scenes/rig-noisy.json"));
  // Where the sun projects (its disc's saturated halo is not symmetric about it).
  BackgroundOptions background;
  background.tanker_pitch_deg = 20.0;
  background.sun = SunOptions{180.0, 5.0, "test"};
  const Camera left = LoadRig(SourcePath("scenes/rig-noisy.json")).left;
  const Eigen::Vector3d ray =
      left.tanker_from_camera.linear().transpose() * LevelFromTanker(background).transpose() * SunInLevel(background);
  ASSERT_GT(ray.z(), 0.0);
  const Eigen::Vector2d sun(511.5 + 900.0 * ray.x() / ray.z(), 383.5 + 900.0 * ray.y() / ray.z());
  const Eigen::Vector2d c(511.5, 383.5), expected = c - 0.6 * (sun - c);
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  int bright = 0;
  for (int v = 0; v < with.rows; ++v) {
    for (int u = 0; u < with.cols; ++u) {
      if (int(with.at<uint8_t>(v, u)) - int(without.at<uint8_t>(v, u)) < 20) continue;
      centroid += Eigen::Vector2d(u, v);
      ++bright;
    }
  }
  ASSERT_GT(bright, 0);
  centroid /= bright;
  std::printf("ghost: %d px centred at %.2f %.2f, expected %.2f %.2f\n", bright, centroid.x(), centroid.y(),
              expected.x(), expected.y());
  EXPECT_NEAR((centroid - expected).norm(), 0.0, 0.5) << centroid.transpose() << " vs " << expected.transpose();
  EXPECT_NEAR(bright, kPi * 15.0 * 15.0, 0.1 * kPi * 15.0 * 15.0);  // the disc
  const nlohmann::json manifest = ReadJsonFile(dir / "with" / "manifest.json");
  EXPECT_EQ(manifest.at("image").at("sensor").at("flare_ghosts").at(0).at("radius_px"), 15.0);
  EXPECT_TRUE(manifest.at("image").at("sensor").contains("lens_flare"));
}

}  // namespace
}  // namespace aar
