// The distortion resampling (renderer/lens_distortion.h), pure CPU: the
// margin, colour through the inverse map, truth by the nearest sample.

#include "aar/renderer/lens_distortion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "aar/error.h"
#include "aar/lens.h"

namespace aar {
namespace {

Intrinsics DistortedCamera() {
  Intrinsics k;
  k.distortion = {-0.15, 0.05, 1e-4, -1e-4, 0.0};
  return k;
}

// A smooth test pattern in pinhole pixel coordinates (periods of 100-200 px).
double Pattern(double x, double y) { return 0.5 + 0.2 * std::sin(x / 23.0) * std::cos(y / 31.0); }

TEST(LensResampler, BarrelDistortionNeedsAMarginAroundThePinholeImage) {
  const Intrinsics k = DistortedCamera();
  const PixelMargin m = LensResampler::RequiredMargin(k, "left");
  // The corners see about 6 % further out than the pinhole image: some 30-40 px each side, plus the filter.
  EXPECT_GT(m.left, 20);
  EXPECT_LT(m.left, 80);
  EXPECT_GT(m.top, 20);
  EXPECT_LT(m.top, 80);
  const LensResampler lens(k, m, "left");
  EXPECT_EQ(lens.pinhole().width_px, 1024 + m.left + m.right);
  EXPECT_EQ(lens.pinhole().height_px, 768 + m.top + m.bottom);
  EXPECT_EQ(lens.pinhole().cx_px, 511.5 + m.left);
  EXPECT_TRUE(lens.pinhole().distortion.IsZero());
  EXPECT_EQ(lens.pinhole().fx_px, 900.0);
  // A margin too small for the filter is refused.
  EXPECT_THROW({ const LensResampler small(k, PixelMargin{2, 2, 2, 2}, "left"); }, Error);
}

TEST(LensResampler, ColourFollowsTheInverseMapAndAUniformSkyStaysExact) {
  const Intrinsics k = DistortedCamera();
  const PixelMargin m = LensResampler::RequiredMargin(k, "left");
  const LensResampler lens(k, m, "left");
  const Intrinsics& p = lens.pinhole();
  LinearImage pinhole;
  pinhole.width = p.width_px;
  pinhole.height = p.height_px;
  pinhole.rgb.resize(static_cast<size_t>(p.width_px) * p.height_px * 3);
  for (int y = 0; y < p.height_px; ++y) {
    for (int x = 0; x < p.width_px; ++x) {
      const size_t i = (static_cast<size_t>(y) * p.width_px + x) * 3;
      pinhole.rgb[i] = static_cast<float>(Pattern(x, y));
      pinhole.rgb[i + 1] = 0.25f;  // uniform channel
      pinhole.rgb[i + 2] = static_cast<float>(Pattern(y, x));
    }
  }
  const LinearImage out = lens.ResampleColor(pinhole);
  ASSERT_EQ(out.width, 1024);
  ASSERT_EQ(out.height, 768);
  double worst = 0.0;
  for (int v = 0; v < 768; v += 7) {
    for (int u = 0; u < 1024; u += 7) {
      // The pinhole position of the output pixel's ray, from the lens model directly.
      const Eigen::Vector2d x = *Undistort(k.distortion, Eigen::Vector2d((u - 511.5) / 900.0, (v - 383.5) / 900.0));
      const double sx = 900.0 * x.x() + p.cx_px, sy = 900.0 * x.y() + p.cy_px;
      const size_t i = (static_cast<size_t>(v) * 1024 + u) * 3;
      worst = std::max(worst, std::abs(out.rgb[i] - Pattern(sx, sy)));
      worst = std::max(worst, std::abs(out.rgb[i + 2] - Pattern(sy, sx)));
      ASSERT_EQ(out.rgb[i + 1], 0.25f) << u << "," << v;
    }
  }
  EXPECT_LT(worst, 2e-3);
}

// The resampler keeps its last render: the next one recomputes only the
// pixels a change reaches. A textured background with a patch that moves
// from frame to frame gives, frame after frame, the bytes of a resampler
// that has seen nothing before.
TEST(LensResampler, ARepeatedBackgroundGivesTheBytesOfAWholeResampling) {
  const Intrinsics k = DistortedCamera();
  const PixelMargin m = LensResampler::RequiredMargin(k, "left");
  const LensResampler lens(k, m, "left");
  const Intrinsics& p = lens.pinhole();
  for (int frame = 0; frame < 4; ++frame) {
    LinearImage pinhole;
    pinhole.width = p.width_px;
    pinhole.height = p.height_px;
    pinhole.rgb.resize(static_cast<size_t>(p.width_px) * p.height_px * 3);
    for (int y = 0; y < p.height_px; ++y) {
      for (int x = 0; x < p.width_px; ++x) {
        const size_t i = (static_cast<size_t>(y) * p.width_px + x) * 3;
        const bool patch = std::abs(x - 300 - 150 * frame) < 40 && std::abs(y - 200 - 90 * frame) < 30;
        for (int c = 0; c < 3; ++c) pinhole.rgb[i + c] = static_cast<float>(patch ? 0.9 : Pattern(x + 7 * c, y));
      }
    }
    if (frame == 2) pinhole.rgb[0] = 0.0f;  // a change at the very corner too
    const LinearImage kept = lens.ResampleColor(pinhole);
    const LinearImage fresh = LensResampler(k, m, "left").ResampleColor(pinhole);
    EXPECT_TRUE(kept.rgb == fresh.rgb) << "frame " << frame;
  }
}

TEST(LensResampler, TruthTakesTheNearestSampleNeverBlended) {
  const Intrinsics k = DistortedCamera();
  const LensResampler lens(k, LensResampler::RequiredMargin(k, "left"), "left");
  const Intrinsics& p = lens.pinhole();
  GroundTruthImage pinhole;
  pinhole.width = p.width_px;
  pinhole.height = p.height_px;
  const size_t n = static_cast<size_t>(p.width_px) * p.height_px;
  for (size_t i = 0; i < n; ++i) {
    pinhole.depth_m.push_back(static_cast<float>(i));  // every pixel its own depth: any blend would show
    pinhole.object_id.push_back(static_cast<uint8_t>(i % 3));
  }
  const GroundTruthImage out = lens.ResampleTruth(pinhole);
  for (int v = 0; v < 768; v += 5) {
    for (int u = 0; u < 1024; u += 5) {
      const Eigen::Vector2d x = *Undistort(k.distortion, Eigen::Vector2d((u - 511.5) / 900.0, (v - 383.5) / 900.0));
      const long sx = std::lround(900.0 * x.x() + p.cx_px), sy = std::lround(900.0 * x.y() + p.cy_px);
      const size_t source = static_cast<size_t>(sy) * p.width_px + static_cast<size_t>(sx);
      const size_t i = static_cast<size_t>(v) * 1024 + u;
      ASSERT_EQ(out.depth_m[i], static_cast<float>(source)) << u << "," << v;
      ASSERT_EQ(out.object_id[i], source % 3) << u << "," << v;
    }
  }
}

}  // namespace
}  // namespace aar
