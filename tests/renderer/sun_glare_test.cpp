// The sun's veiling glare (sun_glare.h; docs/rendering.md, "Veiling glare of
// the sun"): the spread function's integral, the veil at a pixel against the
// formula, the veil's flux over a wide image against the fraction of the
// sun's irradiance, nothing with the sun behind the lens, and a rendered
// dataset whose rig declares glare.

#include "aar/renderer/sun_glare.h"

#include <gtest/gtest.h>

#include <cmath>
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
constexpr double kDeg = kPi / 180.0;

TEST(SunGlare, TheSpreadFunctionHoldsTheFractionAroundTheSource) {
  const double fraction = 0.03, core = 0.5 * kDeg;
  // Midpoint rule on a log-spaced grid of theta, 2 pi theta G(theta) d theta out to 90 deg.
  double total = 0.0;
  const int n = 200000;
  const double lo = std::log(1e-7), hi = std::log(kPi / 2.0);
  for (int i = 0; i < n; ++i) {
    const double a = lo + (hi - lo) * (i + 0.5) / n, theta = std::exp(a), dtheta = theta * (hi - lo) / n;
    total += 2.0 * kPi * theta * GlareSpread(theta, fraction, core) * dtheta;
  }
  // The plane's integral to theta_max: fraction (1 - core / sqrt(core^2 + theta_max^2)).
  const double expected = fraction * (1.0 - core / std::hypot(core, kPi / 2.0));
  EXPECT_NEAR(total, expected, 1e-4 * expected);
  EXPECT_NEAR(GlareSpread(0.0, fraction, core), fraction / (2.0 * kPi * core * core), 1e-9);
}

// A camera of scenes/rig.json with the sun `theta` from the ray through pixel (u, v).
Camera RigLeft() { return LoadRig(SourcePath("scenes/rig.json")).left; }

Eigen::Vector3d RayInTanker(const Camera& camera, double u, double v) {
  const Intrinsics& k = camera.intrinsics;
  return (camera.tanker_from_camera.linear() * Eigen::Vector3d((u - k.cx_px) / k.fx_px, (v - k.cy_px) / k.fy_px, 1.0))
      .normalized();
}

TEST(SunGlare, TheVeilIsTheSpreadOfTheSunsIrradianceAtEachPixel) {
  const Camera camera = RigLeft();
  const Eigen::Vector3d sun = RayInTanker(camera, 300.0, 200.0);
  const Eigen::Vector3d light(0.7, 0.6, 0.5);
  const SunGlare glare(camera, sun, light, 0.02, 0.5);
  const double aperture = (camera.tanker_from_camera.linear().transpose() * sun).z();
  for (const auto& [u, v] : {std::pair{300, 200}, std::pair{310, 200}, std::pair{800, 600}, std::pair{0, 767}}) {
    const double theta = std::acos(std::min(1.0, RayInTanker(camera, u, v).dot(sun)));
    const double g = GlareSpread(theta, 0.02, 0.5 * kDeg);
    const size_t i = (static_cast<size_t>(v) * camera.intrinsics.width_px + u) * 3;
    for (int c = 0; c < 3; ++c) {
      const double expected = g * kPi * aperture * light[c];
      EXPECT_NEAR(glare.veil()[i + c], expected, 2e-3 * expected + 1e-9) << u << "," << v;
    }
  }
  // Applied: the radiance plus the veil, the image otherwise untouched.
  LinearImage image{
      camera.intrinsics.width_px, camera.intrinsics.height_px,
      std::vector<float>(static_cast<size_t>(camera.intrinsics.width_px) * camera.intrinsics.height_px * 3, 0.25f)};
  const LinearImage out = glare.Apply(image, SensorExposure{});
  for (size_t i = 0; i < out.rgb.size(); i += 9973) EXPECT_EQ(out.rgb[i], 0.25f + glare.veil()[i]);
  EXPECT_THROW(glare.Apply(LinearImage{4, 4, std::vector<float>(48, 0.0f)}, SensorExposure{}), Error);
}

// Over a wide image (fx 120 px: +-77 deg across) with the sun on the axis, the
// veil's radiance summed over the pixels' solid angles is the fraction of the
// sun's irradiance that the spread function puts inside the frame.
TEST(SunGlare, TheVeilsFluxIsTheFractionOfTheSunsIrradiance) {
  Camera camera = RigLeft();
  camera.intrinsics.fx_px = camera.intrinsics.fy_px = 120.0;
  const Eigen::Vector3d sun = camera.tanker_from_camera.linear().col(2);
  const double fraction = 0.02, core_deg = 2.0;  // a core of 4 px: the pixel sum resolves it
  const SunGlare glare(camera, sun, Eigen::Vector3d::Constant(1.0 / kPi), fraction, core_deg);
  const Intrinsics& k = camera.intrinsics;
  double flux = 0.0, inside = 0.0;
  for (int v = 0; v < k.height_px; ++v) {
    for (int u = 0; u < k.width_px; ++u) {
      const double x = (u - k.cx_px) / k.fx_px, y = (v - k.cy_px) / k.fy_px;
      const double cos_axis = 1.0 / std::sqrt(1.0 + x * x + y * y);
      const double solid_angle = std::pow(cos_axis, 3.0) / (k.fx_px * k.fy_px);
      flux += glare.veil()[(static_cast<size_t>(v) * k.width_px + u) * 3] * solid_angle;
      inside += GlareSpread(std::acos(cos_axis), fraction, core_deg * kDeg) * solid_angle;
    }
  }
  EXPECT_NEAR(flux, inside, 2e-3 * inside);  // the veil is the spread function of an irradiance of 1
  EXPECT_GT(inside, 0.95 * fraction);        // and nearly all of it falls inside this frame
}

TEST(SunGlare, NoVeilWithTheSunBehindTheLens) {
  const Camera camera = RigLeft();
  const Eigen::Vector3d behind = -camera.tanker_from_camera.linear().col(2);
  const SunGlare glare(camera, behind, Eigen::Vector3d::Constant(0.75), 0.05, 1.0);
  for (float value : glare.veil()) ASSERT_EQ(value, 0.0f);
}

// A rig whose sensor declares glare, the sun 5 deg up aft and the tanker
// pitched 20 deg nose down, so that it is in view (8 deg below the top edge): the image brightens towards the sun, and
// the manifest's sensor records the glare; the default sun (behind the
// cameras) leaves the images as they are without glare.
TEST(SunGlare, ARigWithGlareBrightensTheImageTowardsTheSun) {
  TempDir dir("sun-glare");
  const std::filesystem::path path = dir / "path.csv";
  WriteFileAtomic(path, "time_s,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg\n0.0,200.0,0.0,0.0,0.0,0.0,0.0\n");
  nlohmann::json rig = ReadJsonFile(SourcePath("scenes/rig-noisy.json"));
  rig["sensor"]["glare_fraction"] = 0.02;
  const std::filesystem::path glare_rig = dir / "rig-glare.json";
  WriteFileAtomic(glare_rig, rig.dump(2));
  auto render = [&](const std::string& name, const std::filesystem::path& rig_path, bool sun_in_view) {
    RenderJobOptions o;
    o.output = dir / name;
    o.rig = rig_path;
    o.receiver_model = SourcePath("scenes/c12.glb");
    o.tanker_model = SourcePath("scenes/kc46.glb");
    o.flight_path = path;
    o.progress = false;
    o.msaa = 1;
    o.background.kind = BackgroundKind::kSky;
    if (sun_in_view) {
      o.background.tanker_pitch_deg = 20.0;
      o.background.sun = SunOptions{180.0, 5.0, "test"};
    }
    RenderFlightPathJob(o);
    return cv::imread((o.output / ReadSidecar(SidecarPath(o.output, "frame", 0)).files.at("left").path).string(),
                      cv::IMREAD_GRAYSCALE);
  };
  const cv::Mat with = render("with", glare_rig, true),
                without = render("without", SourcePath("scenes/rig-noisy.json"), true);
  // The disc (saturated) without glare, then the gain around it: 15-40 px
  // from its centre, and 250-300 px, where the spread has fallen 60-fold.
  cv::Point2d centre(0.0, 0.0);
  int disc = 0;
  for (int v = 0; v < without.rows; ++v) {
    for (int u = 0; u < without.cols; ++u) {
      if (without.at<uint8_t>(v, u) < 250) continue;
      centre += cv::Point2d(u, v);
      ++disc;
    }
  }
  ASSERT_GT(disc, 30);
  centre *= 1.0 / disc;
  double near_gain = 0.0, far_gain = 0.0;
  int near = 0, far = 0;
  for (int v = 0; v < without.rows; ++v) {
    for (int u = 0; u < without.cols; ++u) {
      const double r = std::hypot(u - centre.x, v - centre.y);
      const double gain = double(with.at<uint8_t>(v, u)) - double(without.at<uint8_t>(v, u));
      if (r >= 15.0 && r < 40.0) near_gain += gain, ++near;
      if (r >= 250.0 && r < 300.0) far_gain += gain, ++far;
    }
  }
  near_gain /= near;
  far_gain /= far;
  EXPECT_GT(near_gain, 3.0);  // 8-bit codes, the sky next to the disc clipping at white already
  EXPECT_GT(near_gain, 10.0 * std::max(far_gain, 0.1)) << far_gain;
  const nlohmann::json manifest = ReadJsonFile(dir / "with" / "manifest.json");
  EXPECT_EQ(manifest.at("image").at("sensor").at("glare_fraction"), 0.02);
  const cv::Mat behind_with = render("behind-with", glare_rig, false);
  const cv::Mat behind_without = render("behind-without", SourcePath("scenes/rig-noisy.json"), false);
  EXPECT_EQ(cv::norm(behind_with, behind_without, cv::NORM_INF), 0.0);
}

}  // namespace
}  // namespace aar
