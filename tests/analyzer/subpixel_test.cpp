// Symmetric sub-pixel refinement on synthetic pairs of a textured plane.

#include "aar/analyzer/subpixel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <opencv2/core.hpp>
#include <optional>
#include <random>
#include <vector>

#include "aar/error.h"
#include "synthetic_texture.h"

namespace aar {
namespace {

using test::Texture;

// A plane whose disparity is d(x, y) = a x + b y + c at left pixel (x, y).
struct Plane {
  double a, b, c;
  double At(double x, double y) const { return a * x + b * y + c; }
};

// The left image shows the texture at (x, y); the right one shows at
// (x, y) the surface point whose left pixel x_l satisfies x_l - d(x_l, y) = x.
void RenderPair(const Texture& texture, const Plane& plane, cv::Mat& left, cv::Mat& right) {
  const int width = 160, height = 120;
  left.create(height, width, CV_8UC1);
  right.create(height, width, CV_8UC1);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const double x_left = (x + plane.b * y + plane.c) / (1.0 - plane.a);
      left.at<uchar>(y, x) = cv::saturate_cast<uchar>(texture(x, y));
      right.at<uchar>(y, x) = cv::saturate_cast<uchar>(texture(x_left, y));
    }
  }
}

struct Errors {
  double mean = 0.0, rms = 0.0, slope_u = 0.0, slope_v = 0.0;
  size_t refined = 0;
};

// Refines every pixel of the image's middle from the true disparity rounded
// to the nearest 1/16 px plus 0.3 px, and measures the result against the
// plane's disparity at the refined left column.
Errors Measure(const Plane& plane, bool slanted, SubpixelInterpolation interpolation = SubpixelInterpolation::kLinear) {
  double sum = 0.0, squared = 0.0, slope_u = 0.0, slope_v = 0.0;
  size_t count = 0;
  for (unsigned seed = 1; seed <= 3; ++seed) {
    cv::Mat left, right;
    RenderPair(Texture(seed), plane, left, right);
    SubpixelOptions options;
    options.slanted = slanted;
    options.interpolation = interpolation;
    const SubpixelRefiner refiner(left, right, options);
    for (int v = 40; v < 80; v += 3) {
      for (int u = 70; u < 130; u += 3) {
        const double start = std::round(16.0 * plane.At(u, v)) / 16.0 + 0.3;
        const auto refined = refiner.Refine(u, v, start);
        if (!refined) continue;
        const double error = refined->disparity_px - plane.At(refined->u_px, v);
        sum += error;
        squared += error * error;
        slope_u += refined->slope_u;
        slope_v += refined->slope_v;
        ++count;
      }
    }
  }
  const double n = static_cast<double>(count);
  std::printf("%s, %s: %zu refined, error mean %+.4f rms %.4f px, slopes %+.4f %+.4f\n", slanted ? "slanted" : "flat",
              ToString(interpolation).c_str(), count, sum / n, std::sqrt(squared / n), slope_u / n, slope_v / n);
  return {sum / n, std::sqrt(squared / n), slope_u / n, slope_v / n, count};
}

TEST(Subpixel, BothWindowsAgreeOnAFrontoParallelPlane) {
  // Linear interpolation locks both a little towards integer disparities
  // (here -0.03 px at a fraction of 0.37); on a plane facing the cameras the
  // slanted window finds no slope and the same disparity as the flat one.
  const Plane plane{0.0, 0.0, 20.37};
  const Errors flat = Measure(plane, false);
  const Errors slanted = Measure(plane, true);
  for (const Errors& e : {flat, slanted}) {
    EXPECT_GT(e.refined, 600u);
    EXPECT_LT(e.rms, 0.04);
  }
  EXPECT_NEAR(slanted.mean, flat.mean, 0.005);
  EXPECT_NEAR(slanted.slope_u, 0.0, 1e-3);
  EXPECT_NEAR(slanted.slope_v, 0.0, 1e-3);
}

TEST(Subpixel, SlantedWindowsFollowTheDisparitySlope) {
  // About the steepest slopes of the receiver's surface at 35 m (true
  // dd/du and dd/dv up to 0.2): a flat window's disparity errs by the slope
  // times its texture's centre of mass; the slanted one solves for the slope.
  const Plane plane{0.08, 0.12, 14.61 - 0.08 * 100.0 - 0.12 * 60.0};
  const Errors flat = Measure(plane, false);
  const Errors slanted = Measure(plane, true);
  EXPECT_GT(slanted.refined, 600u);
  EXPECT_LT(slanted.rms, 0.03);
  EXPECT_LT(slanted.rms, 0.5 * flat.rms);
  EXPECT_NEAR(slanted.slope_u, plane.a, 0.01);
  EXPECT_NEAR(slanted.slope_v, plane.b, 0.01);
  EXPECT_EQ(flat.slope_u, 0.0);
}

TEST(Subpixel, BSplineRemovesLinearInterpolationsOvershoot) {
  // Linear interpolation lags the shift it is asked for, and the mirrored
  // offsets add the lags: the estimate overshoots its distance from the
  // integer it starts from (here 0.3 px above the true disparity, so the
  // error is -0.03 px at most fractions). The cubic B-spline follows the
  // band-limited texture's shift.
  for (const double fraction : {0.2, 0.37, 0.45, 0.55, 0.63, 0.8}) {
    const Plane plane{0.0, 0.0, 20.0 + fraction};
    const Errors linear = Measure(plane, true);
    const Errors spline = Measure(plane, true, SubpixelInterpolation::kCubicBSpline);
    EXPECT_GT(spline.refined, 600u);
    EXPECT_GT(std::abs(linear.mean), 0.01) << fraction;
    EXPECT_LT(std::abs(spline.mean), 0.3 * std::abs(linear.mean)) << fraction;
    EXPECT_LT(spline.rms, linear.rms) << fraction;
  }
}

TEST(SubpixelBSpline, InterpolatesSamplesAndCubics) {
  // Without a prefilter the spline passes through the samples, and it
  // reproduces a cubic (here a quadratic) exactly away from the ends.
  std::vector<uint8_t> row(40);
  for (int x = 0; x < 40; ++x) row[static_cast<size_t>(x)] = static_cast<uint8_t>(0.15 * (x - 20) * (x - 20));
  std::vector<float> c(row.size());
  SplineRowCoefficients(row.data(), 40, 0.0, c.data());
  for (const double x : {10.0, 12.25, 17.5, 20.0, 26.8}) {
    float value = 0.0f, derivative = 0.0f;
    SampleSpline(c.data(), x, &value, &derivative);
    if (x == std::floor(x)) {
      EXPECT_NEAR(value, row[static_cast<size_t>(x)], 1e-4) << x;
    } else {
      // Between samples the quadratic's integer rounding is not a quadratic;
      // compare with the spline of the unrounded samples' neighbours.
      const double a = x - std::floor(x), y0 = row[static_cast<size_t>(x)], y1 = row[static_cast<size_t>(x) + 1];
      EXPECT_GT(value, std::min(y0, y1) - 1.0) << x;
      EXPECT_LT(value, std::max(y0, y1) + 1.0) << x;
      EXPECT_NEAR(derivative, 0.3 * (x - 20), 1.0 + a) << x;
    }
  }
}

TEST(SubpixelBSpline, PrefilterMakesNoiseVarianceFlat) {
  // White noise interpolated at fraction a has variance sum_k h_a[k]^2,
  // h_a the response to a unit sample k; the default prefilter is the
  // smallest tenth of a pixel that keeps its spread over a below 2.5 %.
  const auto spread = [](double sigma) {
    const int n = 81, centre = 40;
    std::vector<std::vector<float>> responses;
    for (int k = 0; k < n; ++k) {
      std::vector<uint8_t> row(n, 0);
      row[static_cast<size_t>(k)] = 1;
      responses.emplace_back(n);
      SplineRowCoefficients(row.data(), n, sigma, responses.back().data());
    }
    double lowest = 1e9, highest = 0.0;
    for (int step = 0; step <= 10; ++step) {
      double variance = 0.0;
      for (const auto& c : responses) {
        float value = 0.0f, derivative = 0.0f;
        SampleSpline(c.data(), centre + 0.05 * step, &value, &derivative);
        variance += static_cast<double>(value) * value;
      }
      lowest = std::min(lowest, variance);
      highest = std::max(highest, variance);
    }
    return (highest - lowest) / (0.5 * (highest + lowest));
  };
  const double chosen = SubpixelOptions{}.prefilter_sigma_px;
  EXPECT_LT(spread(chosen), 0.025);
  EXPECT_GT(spread(chosen - 0.1), 0.025);
  EXPECT_GT(spread(0.0), 0.2);  // the spline alone: about 28 %
}

TEST(Subpixel, ARegionOfTheImagesRefinesLikeTheWholeImages) {
  // The tracking mode hands the refiner the rectified region only (with its
  // origin); rows are converted on first use, so the order of the queries
  // must not matter either: the same bytes in, the same answers out.
  const Plane plane{0.08, 0.12, 14.61 - 0.08 * 100.0 - 0.12 * 60.0};
  cv::Mat left, right;
  RenderPair(Texture(7), plane, left, right);
  const cv::Rect region(30, 20, 120, 90);
  const SubpixelRefiner whole(left, right, SubpixelOptions{});
  const SubpixelRefiner part(left(region).clone(), right(region).clone(), SubpixelOptions{}, region.tl());
  const auto start_at = [&](int u, int v) { return std::round(16.0 * plane.At(u, v)) / 16.0 + 0.3; };
  std::map<std::pair<int, int>, std::optional<RefinedDisparity>> expected;
  for (int v = 40; v < 80; v += 3) {  // top-down on the whole images
    for (int u = 70; u < 130; u += 3) expected[{u, v}] = whole.Refine(u, v, start_at(u, v));
  }
  size_t compared = 0;
  for (int v = 79; v >= 40; v -= 3) {  // bottom-up on the region
    for (int u = 70; u < 130; u += 3) {
      const auto a = part.Refine(u, v, start_at(u, v));
      const auto& b = expected.at({u, v});
      ASSERT_EQ(a.has_value(), b.has_value()) << u << " " << v;
      if (!a) continue;
      EXPECT_EQ(a->disparity_px, b->disparity_px) << u << " " << v;
      EXPECT_EQ(a->u_px, b->u_px);
      EXPECT_EQ(a->slope_u, b->slope_u);
      EXPECT_EQ(a->slope_v, b->slope_v);
      ++compared;
    }
  }
  EXPECT_GT(compared, 200u);
  // A window reaching past the region's edge is refused, not read outside it.
  EXPECT_FALSE(part.Refine(region.x + 3, 60, 10.0).has_value());
}

TEST(Subpixel, ARegionRefinesLikeTheWholeImagesWithTheSpline) {
  // The spline's rows end at the region's edge (mirrored there), which the
  // window's margin keeps a few pixels away: the answers agree to far below
  // the disparity's noise, not to the bit.
  const Plane plane{0.08, 0.12, 14.61 - 0.08 * 100.0 - 0.12 * 60.0};
  cv::Mat left, right;
  RenderPair(Texture(7), plane, left, right);
  const cv::Rect region(30, 20, 120, 90);
  SubpixelOptions options;
  options.interpolation = SubpixelInterpolation::kCubicBSpline;
  const SubpixelRefiner whole(left, right, options);
  const SubpixelRefiner part(left(region).clone(), right(region).clone(), options, region.tl());
  size_t compared = 0;
  for (int v = 40; v < 80; v += 3) {
    for (int u = 70; u < 130; u += 3) {
      const double start = std::round(16.0 * plane.At(u, v)) / 16.0 + 0.3;
      const auto a = part.Refine(u, v, start);
      const auto b = whole.Refine(u, v, start);
      ASSERT_EQ(a.has_value(), b.has_value()) << u << " " << v;
      if (!a) continue;
      EXPECT_NEAR(a->disparity_px, b->disparity_px, 1e-3) << u << " " << v;
      ++compared;
    }
  }
  EXPECT_GT(compared, 200u);
}

TEST(Subpixel, RejectsInvalidOptions) {
  SubpixelOptions options;
  options.max_slope = 0.0;
  EXPECT_THROW(options.Check(), Error);
  options.max_slope = 0.5;
  options.half_window_px = 0;
  EXPECT_THROW(options.Check(), Error);
  options.half_window_px = 4;
  options.prefilter_sigma_px = -0.1;
  EXPECT_THROW(options.Check(), Error);
  EXPECT_THROW(ParseSubpixelInterpolation("cubic"), Error);
  EXPECT_EQ(ParseSubpixelInterpolation("bspline"), SubpixelInterpolation::kCubicBSpline);
}

}  // namespace
}  // namespace aar
