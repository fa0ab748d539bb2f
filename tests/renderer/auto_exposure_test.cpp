// Auto-exposure (auto_exposure.h; docs/rendering.md, "Exposure and night"):
// the controller's first-order lag against its closed form, its one frame of
// delay, convergence with clipped pixels, the exposure's limit; and a render
// whose frames take the schedule's exposures, the same whatever frames a run
// selects.

#include "aar/renderer/auto_exposure.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "../test_support.h"
#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/json_file.h"
#include "aar/renderer/stereo_render_job.h"

namespace aar {
namespace {

using test::SourcePath;
using test::TempDir;

LinearImage Uniform(float value, int pixels = 16) {
  return LinearImage{pixels, 1, std::vector<float>(static_cast<size_t>(pixels) * 3, value)};
}

std::vector<double> Times(size_t n, double dt) {
  std::vector<double> t;
  for (size_t i = 0; i < n; ++i) t.push_back(static_cast<double>(i) * dt);
  return t;
}

// A grey scene of radiance 0.05 at 25 Hz, time constant 0.1 s: e* = log2(0.18
// / 0.05) and e_n - e* = (e_0 - e*) (1 - a)^n, a = 1 - exp(-0.04 / 0.1).
TEST(AutoExposure, TheLagIsFirstOrderTowardsTheTarget) {
  AutoExposureOptions options;
  const AutoExposureSchedule s =
      RunAutoExposure(Times(40, 0.04), 0.0, 1.0, 1.0, options, [](size_t) { return Uniform(0.05f); });
  const double grey = 0.05f;  // as the image holds it
  const double wanted = std::log2(0.18 / grey), keep = std::exp(-0.04 / 0.1);
  ASSERT_EQ(s.ev.size(), 40u);
  for (size_t n = 0; n < s.ev.size(); ++n) {
    EXPECT_NEAR(s.ev[n], wanted - wanted * std::pow(keep, static_cast<double>(n)), 1e-9) << n;
    EXPECT_NEAR(s.metered[n], grey * std::exp2(s.ev[n]), 1e-9) << n;
  }
  EXPECT_NEAR(s.metered.back(), 0.18, 1e-3);
  // No lag: the second frame meets the target.
  options.time_constant_s = 0.0;
  const AutoExposureSchedule now =
      RunAutoExposure(Times(3, 0.04), 0.0, 1.0, 1.0, options, [](size_t) { return Uniform(0.05f); });
  EXPECT_NEAR(now.metered[1], 0.18, 1e-7);
}

// The scene brightens 4x at frame 10: frame 10 still has the exposure it
// would have had (metered 4x brighter), frame 11 is the first to answer.
TEST(AutoExposure, AFrameSetsTheNextFramesExposure) {
  const AutoExposureOptions options;
  const auto scene = [](size_t n) { return Uniform(n < 10 ? 0.05f : 0.2f); };
  const AutoExposureSchedule step = RunAutoExposure(Times(14, 0.04), 0.0, 1.0, 1.0, options, scene);
  const AutoExposureSchedule flat =
      RunAutoExposure(Times(14, 0.04), 0.0, 1.0, 1.0, options, [](size_t) { return Uniform(0.05f); });
  for (size_t n = 0; n <= 10; ++n) EXPECT_EQ(step.ev[n], flat.ev[n]) << n;
  EXPECT_NEAR(step.metered[10], 4.0 * flat.metered[10], 1e-7);
  EXPECT_LT(step.ev[11], flat.ev[11] - 0.5);
}

// Half the pixels at 100 (the sun), half at 0.01, full scale 1: the level
// never exceeds 1 and the exposure settles where 0.5 (100 + 0.01) 2^e = 0.18.
TEST(AutoExposure, ClippedPixelsCountAtFullScaleAndTheExposureStillSettles) {
  LinearImage scene = Uniform(0.01f, 64);
  for (size_t i = 0; i < scene.rgb.size() / 2; ++i) scene.rgb[i] = 100.0f;
  const AutoExposureSchedule s =
      RunAutoExposure(Times(200, 0.04), 0.0, 1.0, 1.0, AutoExposureOptions{}, [&](size_t) { return scene; });
  EXPECT_NEAR(s.metered[0], 0.5 * 1.0 + 0.5 * 0.01, 1e-7);  // the sun's half clipped at 1
  for (size_t n = 1; n < s.ev.size(); ++n) {
    EXPECT_LE(s.metered[n], 1.0);
    EXPECT_LE(s.ev[n], s.ev[n - 1] + 1e-12);
  }
  EXPECT_NEAR(s.ev.back(), std::log2(0.36 / (100.0 + double(0.01f))), 1e-3);
}

// A black scene drives the exposure to the camera's most and keeps it
// there; a bright one at night's render scale meters the same as by day.
TEST(AutoExposure, TheExposureStopsAtTheCamerasMostAndDividesTheRenderScale) {
  AutoExposureOptions options;
  options.max_ev = 9.0;
  const AutoExposureSchedule black =
      RunAutoExposure(Times(200, 0.04), 0.0, 1.0, 1.0, options, [](size_t) { return Uniform(0.0f); });
  EXPECT_NEAR(black.ev.back(), 9.0, 1e-9);
  for (double ev : black.ev) EXPECT_LE(ev, 9.0);
  const AutoExposureSchedule day =
      RunAutoExposure(Times(5, 0.04), 0.0, 1.0, 1.0, AutoExposureOptions{}, [](size_t) { return Uniform(0.05f); });
  const AutoExposureSchedule night = RunAutoExposure(Times(5, 0.04), 0.0, 4096.0, 1.0, AutoExposureOptions{},
                                                     [](size_t) { return Uniform(0.05f * 4096.0f); });
  for (size_t n = 0; n < 5; ++n) EXPECT_NEAR(night.ev[n], day.ev[n], 1e-9);
  options.target = 1.5;
  EXPECT_THROW(options.Check(), Error);
  EXPECT_THROW(RunAutoExposure({0.0, 0.0}, 0.0, 1.0, 1.0, AutoExposureOptions{}, [](size_t) { return Uniform(0.1f); }),
               Error);
}

// Rendered, over terrain, every other frame of the CONOPS path's last 40:
// the frames of a run that selects frames 596:598 are byte for byte those of
// a run of 590:598, both manifests hold the same schedule, and frame 597
// is the frame a fixed --exposure-ev of the schedule's value gives.
TEST(AutoExposure, RenderedFramesTakeTheSchedulesExposureWhateverTheSelection) {
  TempDir dir("auto-exposure");
  auto render = [&](const std::string& name, size_t begin, size_t end, bool automatic, double ev) {
    RenderJobOptions o;
    o.output = dir / name;
    o.receiver_model = SourcePath("scenes/c12.glb");
    o.tanker_model = SourcePath("scenes/kc46.glb");
    o.flight_path = SourcePath("flightpaths/conops.csv");
    o.progress = false;
    o.msaa = 1;
    o.background.kind = BackgroundKind::kTerrain;
    o.selection.begin = begin;
    o.selection.end = end;
    o.exposure_ev = ev;
    if (automatic) o.auto_exposure = AutoExposureOptions{};
    RenderFlightPathJob(o);
    return o.output;
  };
  const std::filesystem::path all = render("all", 590, 598, true, 2.0);
  const std::filesystem::path part = render("part", 596, 598, true, 2.0);
  const nlohmann::json a = ReadJsonFile(all / "manifest.json").at("frames").at("auto_exposure");
  EXPECT_EQ(a, ReadJsonFile(part / "manifest.json").at("frames").at("auto_exposure"));
  const std::vector<double> ev = a.at("ev").get<std::vector<double>>();
  ASSERT_GT(ev.size(), 598u);
  EXPECT_EQ(ev[0], 2.0);
  EXPECT_GT(std::abs(ev[597] - ev[0]), 0.5);  // the camera has moved from where it began
  EXPECT_NEAR(a.at("metered")[597].get<double>(), 0.18, 0.02);
  const std::filesystem::path fixed = render("fixed", 597, 598, false, ev[597]);
  for (size_t i : {596u, 597u}) {
    const FrameSidecar s = ReadSidecar(SidecarPath(all, "frame", i));
    for (const std::string side : {"left", "right"}) {
      const std::string file = s.files.at(side).path;
      EXPECT_EQ(ReadFileBytes(all / file), ReadFileBytes(part / file)) << i << " " << side;
      if (i == 597) {
        EXPECT_EQ(ReadFileBytes(all / file), ReadFileBytes(fixed / file)) << side;
      }
    }
  }
}

}  // namespace
}  // namespace aar
