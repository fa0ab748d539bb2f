#include "aar/analyzer/subpixel.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "aar/error.h"

namespace aar {

void SubpixelOptions::Check() const {
  if (half_window_px < 1 || half_window_px > 32) throw Error("sub-pixel: half_window_px must be in [1, 32]");
  if (max_iterations < 1) throw Error("sub-pixel: max_iterations must be >= 1");
  if (!(tolerance_px > 0.0)) throw Error("sub-pixel: tolerance_px must be positive");
  if (!(max_correction_px > 0.0)) throw Error("sub-pixel: max_correction_px must be positive");
  if (!(min_gradient_energy >= 0.0)) throw Error("sub-pixel: min_gradient_energy must be >= 0");
  if (!(max_slope > 0.0 && max_slope <= 1.0)) throw Error("sub-pixel: max_slope must be in (0, 1]");
  if (!(prefilter_sigma_px >= 0.0 && prefilter_sigma_px <= 4.0)) {
    throw Error("sub-pixel: prefilter_sigma_px must be in [0, 4]");
  }
}

std::string ToString(SubpixelInterpolation interpolation) {
  return interpolation == SubpixelInterpolation::kLinear ? "linear" : "bspline";
}

SubpixelInterpolation ParseSubpixelInterpolation(const std::string& text) {
  if (text == "linear") return SubpixelInterpolation::kLinear;
  if (text == "bspline") return SubpixelInterpolation::kCubicBSpline;
  throw Error("sub-pixel interpolation '" + text + "': expected linear or bspline");
}

void SplineRowCoefficients(const uint8_t* row, int n, double sigma_px, float* coefficients) {
  if (n < 2) throw Error("sub-pixel: a spline row needs at least 2 samples");
  const auto mirror = [n](int k) {
    const int period = 2 * (n - 1);
    k = std::abs(k) % period;
    return k < n ? k : period - k;
  };
  std::vector<double> s(static_cast<size_t>(n));
  if (sigma_px > 0.0) {
    const int radius = static_cast<int>(std::ceil(4.0 * sigma_px));
    std::vector<double> kernel(static_cast<size_t>(radius) + 1);
    double total = 0.0;
    for (int k = 0; k <= radius; ++k) {
      kernel[static_cast<size_t>(k)] = std::exp(-0.5 * k * k / (sigma_px * sigma_px));
      total += (k == 0 ? 1.0 : 2.0) * kernel[static_cast<size_t>(k)];
    }
    for (int x = 0; x < n; ++x) {
      double sum = kernel[0] * row[x];
      for (int k = 1; k <= radius; ++k)
        sum += kernel[static_cast<size_t>(k)] * (row[mirror(x - k)] + row[mirror(x + k)]);
      s[static_cast<size_t>(x)] = sum / total;
    }
  } else {
    for (int x = 0; x < n; ++x) s[static_cast<size_t>(x)] = row[x];
  }
  // The cubic B-spline's recursive prefilter: one causal and one anti-causal
  // first-order pass with the pole z = sqrt(3) - 2, gain 6. The causal pass
  // starts from the mirrored row's sum, truncated where z^k < 1e-10.
  const double z = std::sqrt(3.0) - 2.0;
  const int horizon = static_cast<int>(std::ceil(std::log(1e-10) / std::log(-z)));
  std::vector<double> c(static_cast<size_t>(n));
  double start = 0.0, power = 1.0;
  for (int k = 0; k < horizon; ++k, power *= z) start += power * s[static_cast<size_t>(mirror(k))];
  c[0] = start;
  for (int k = 1; k < n; ++k) c[static_cast<size_t>(k)] = s[static_cast<size_t>(k)] + z * c[static_cast<size_t>(k) - 1];
  const size_t last = static_cast<size_t>(n) - 1;
  double next = z / (z * z - 1.0) * (c[last] + z * c[last - 1]);
  coefficients[last] = static_cast<float>(6.0 * next);
  for (int k = n - 2; k >= 0; --k) {
    next = z * (next - c[static_cast<size_t>(k)]);
    coefficients[k] = static_cast<float>(6.0 * next);
  }
}

void SampleSpline(const float* coefficients, double x, float* value, float* derivative) {
  const int i = static_cast<int>(std::floor(x));
  const float a = static_cast<float>(x - i), b = 1.0f - a;
  const float* c = coefficients + i - 1;
  // The cubic B-spline's weights of the four coefficients around x, and
  // their derivatives.
  const float w0 = b * b * b / 6.0f, w3 = a * a * a / 6.0f;
  const float w1 = 2.0f / 3.0f - a * a + 0.5f * a * a * a, w2 = 2.0f / 3.0f - b * b + 0.5f * b * b * b;
  const float d0 = -0.5f * b * b, d3 = 0.5f * a * a;
  const float d1 = -2.0f * a + 1.5f * a * a, d2 = 2.0f * b - 1.5f * b * b;
  *value = w0 * c[0] + w1 * c[1] + w2 * c[2] + w3 * c[3];
  *derivative = d0 * c[0] + d1 * c[1] + d2 * c[2] + d3 * c[3];
}

SubpixelRefiner::SubpixelRefiner(const cv::Mat& rect_left_gray, const cv::Mat& rect_right_gray,
                                 const SubpixelOptions& options, cv::Point origin)
    : options_(options), origin_(origin) {
  options_.Check();
  if (rect_left_gray.type() != CV_8UC1 || rect_right_gray.type() != CV_8UC1 ||
      rect_left_gray.size() != rect_right_gray.size()) {
    throw Error("sub-pixel: rectified images must be 8-bit grayscale of one size");
  }
  left8_ = rect_left_gray;
  right8_ = rect_right_gray;
  // Allocated, not filled: rows are converted when a window first needs them.
  left_.create(left8_.size(), CV_32FC2);
  right_.create(right8_.size(), CV_32FC2);
  if (options_.interpolation == SubpixelInterpolation::kCubicBSpline) {
    left_spline_.create(left8_.size(), CV_32FC1);
    right_spline_.create(right8_.size(), CV_32FC1);
  }
  row_ready_.assign(static_cast<size_t>(left8_.rows), 0);
  const size_t side = 2 * static_cast<size_t>(options_.half_window_px) + 1;
  residuals_.resize(side * side);
  gradients_.resize(side * side);
}

void SubpixelRefiner::PrepareRows(int first, int last) const {
  for (int y = first; y <= last; ++y) {
    if (row_ready_[static_cast<size_t>(y)]) continue;
    row_ready_[static_cast<size_t>(y)] = 1;
    for (const auto& [gray, out] : {std::pair{&left8_, &left_}, std::pair{&right8_, &right_}}) {
      const uint8_t* g = gray->ptr<uint8_t>(y);
      float* o = out->ptr<float>(y);
      const int last = gray->cols - 1;
      // Intensity and central difference (I(x+1) - I(x-1)) / 2, the edge
      // pixels replicated.
      o[0] = g[0];
      o[1] = 0.5f * static_cast<float>(g[std::min(1, last)] - g[0]);
      for (int x = 1; x < last; ++x) {
        o[2 * x] = g[x];
        o[2 * x + 1] = 0.5f * static_cast<float>(g[x + 1] - g[x - 1]);
      }
      o[2 * last] = g[last];
      o[2 * last + 1] = 0.5f * static_cast<float>(g[last] - g[std::max(last - 1, 0)]);
    }
    if (options_.interpolation == SubpixelInterpolation::kCubicBSpline) {
      SplineRowCoefficients(left8_.ptr<uint8_t>(y), left8_.cols, options_.prefilter_sigma_px,
                            left_spline_.ptr<float>(y));
      SplineRowCoefficients(right8_.ptr<uint8_t>(y), right8_.cols, options_.prefilter_sigma_px,
                            right_spline_.ptr<float>(y));
    }
  }
}

double SubpixelRefiner::GradientEnergy(int u, int v, double d_int) const {
  const int h = options_.half_window_px;
  const int ur = u - static_cast<int>(d_int);
  double sum = 0.0, squared = 0.0;
  for (int i = -h; i <= h; ++i) {
    const float* l = left_.ptr<float>(v + i);
    const float* r = right_.ptr<float>(v + i);
    for (int j = -h; j <= h; ++j) {
      const double g = 0.5 * (l[2 * (u + j) + 1] + r[2 * (ur + j) + 1]);
      sum += g;
      squared += g * g;
    }
  }
  return squared - sum * sum / ((2 * h + 1) * (2 * h + 1));
}

void SubpixelRefiner::SampleWindow(int u, int v, double d_int, const Eigen::Vector3d& p, float* e, float* g) const {
  const int h = options_.half_window_px;
  const bool spline = options_.interpolation == SubpixelInterpolation::kCubicBSpline;
  for (int i = -h; i <= h; ++i) {
    const float* l = left_.ptr<float>(v + i);
    const float* r = right_.ptr<float>(v + i);
    const float* ls = spline ? left_spline_.ptr<float>(v + i) : nullptr;
    const float* rs = spline ? right_spline_.ptr<float>(v + i) : nullptr;
    // Sample (i, j) lies at xl = u + j + shift / 2 in the left image and
    // xr = u + j - d_int - shift / 2 in the right one.
    const double row_shift = p(0) + p(2) * i - p(1) * h;
    double xl = u - h + 0.5 * row_shift, xr = u - h - d_int - 0.5 * row_shift;
    const double step_l = 1.0 + 0.5 * p(1), step_r = 1.0 - 0.5 * p(1);
    for (int j = -h; j <= h; ++j, xl += step_l, xr += step_r, ++e, ++g) {
      // e = I_L(xl) - I_R(xr); de/d shift = (I_L'(xl) + I_R'(xr)) / 2.
      if (spline) {
        float vl, gl, vr, gr;
        SampleSpline(ls, xl, &vl, &gl);
        SampleSpline(rs, xr, &vr, &gr);
        *e = vl - vr;
        *g = 0.5f * (gl + gr);
      } else {
        // Interleaved (intensity, derivative) pairs: one index per image.
        const int il = static_cast<int>(xl), ir = static_cast<int>(xr);
        const float al = static_cast<float>(xl - il), ar = static_cast<float>(xr - ir);
        const float* pl = l + 2 * il;
        const float* pr = r + 2 * ir;
        *e = (pl[0] + al * (pl[2] - pl[0])) - (pr[0] + ar * (pr[2] - pr[0]));
        *g = 0.5f * ((pl[1] + al * (pl[3] - pl[1])) + (pr[1] + ar * (pr[3] - pr[1])));
      }
    }
  }
}

SubpixelRefiner::NormalEquations SubpixelRefiner::Normals(const float* e, const float* g) const {
  // The Jacobian of sample (i, j) (row, column offsets) is g (1, j, i), so
  // per row only sums of g, g j, g^2, g^2 j, g^2 j^2, e, e g and e g j are
  // needed (in float, over one row); the row offset i multiplies them
  // afterwards (in double).
  const int h = options_.half_window_px;
  double sum_e = 0.0, sum_g = 0.0, sum_gj = 0.0, sum_gi = 0.0;
  double sum_eg = 0.0, sum_egj = 0.0, sum_egi = 0.0;
  double s00 = 0.0, s01 = 0.0, s02 = 0.0, s11 = 0.0, s12 = 0.0, s22 = 0.0;
  for (int i = -h; i <= h; ++i) {
    float re = 0.0f, rg = 0.0f, rgj = 0.0f, rg2 = 0.0f, rg2j = 0.0f, rg2jj = 0.0f, reg = 0.0f, regj = 0.0f;
    for (int j = -h; j <= h; ++j, ++e, ++g) {
      const float fj = static_cast<float>(j), g2 = *g * *g, eg = *e * *g;
      re += *e;
      rg += *g;
      rgj += *g * fj;
      rg2 += g2;
      rg2j += g2 * fj;
      rg2jj += g2 * fj * fj;
      reg += eg;
      regj += eg * fj;
    }
    const double di = i;
    sum_e += re;
    sum_g += rg;
    sum_gj += rgj;
    sum_gi += di * rg;
    sum_eg += reg;
    sum_egj += regj;
    sum_egi += di * reg;
    s00 += rg2;
    s01 += rg2j;
    s02 += di * rg2;
    s11 += rg2jj;
    s12 += di * rg2j;
    s22 += di * di * rg2;
  }
  // Zero-mean normal equations: sum (J - mean J)(J - mean J)^T =
  // sum J J^T - n mean_J mean_J^T, likewise for J e.
  const double n = (2 * h + 1) * (2 * h + 1);
  NormalEquations out;
  const Eigen::Vector3d mean_j = Eigen::Vector3d(sum_g, sum_gj, sum_gi) / n;
  out.jj << s00, s01, s02, s01, s11, s12, s02, s12, s22;
  out.jj -= n * mean_j * mean_j.transpose();
  out.je = Eigen::Vector3d(sum_eg, sum_egj, sum_egi) - sum_e * mean_j;
  return out;
}

std::optional<RefinedDisparity> SubpixelRefiner::Refine(int u_image, int v_image, double disparity_px) const {
  const int u = u_image - origin_.x, v = v_image - origin_.y;
  const int h = options_.half_window_px;
  const double d_int = std::round(disparity_px);
  const double start = disparity_px - d_int;
  // Both windows need their samples and the next column inside the image;
  // a slanted window's columns shift by up to max_slope * h more.
  const bool spline = options_.interpolation == SubpixelInterpolation::kCubicBSpline;
  const int margin =
      h + 2 + (options_.slanted ? static_cast<int>(std::ceil(options_.max_slope * h)) : 0) + (spline ? 1 : 0);
  if (v - h < 0 || v + h >= left_.rows || u - margin < 0 || u + margin >= left_.cols || u - d_int - margin < 0 ||
      u - d_int + margin >= left_.cols) {
    return std::nullopt;
  }
  PrepareRows(v - h, v + h);
  // The spline's gradients are smoothed by the prefilter: its texture test
  // reads the unfiltered images at the starting integer disparity instead.
  if (spline && !(GradientEnergy(u, v, d_int) >= options_.min_gradient_energy)) return std::nullopt;
  // Parameters: delta (the centre's disparity minus d_int), and with a
  // slanted window its change per column and per row, so that sample (i, j)
  // is shifted by delta + a j + b i. One Gauss-Newton step solves the
  // zero-mean normal equations (the windows' brightness offset is not a
  // disparity) for all of them.
  Eigen::Vector3d p(start, 0.0, 0.0);
  RefinedDisparity out;
  std::vector<float>& e = residuals_;
  std::vector<float>& g = gradients_;
  const int max_iterations = options_.slanted ? 2 * options_.max_iterations : options_.max_iterations;
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    SampleWindow(u, v, d_int, p, e.data(), g.data());
    const NormalEquations normals = Normals(e.data(), g.data());
    const Eigen::Matrix3d& jj = normals.jj;
    if (!spline && !(jj(0, 0) >= options_.min_gradient_energy)) return std::nullopt;
    if (!(jj(0, 0) > 0.0)) return std::nullopt;
    Eigen::Vector3d step = Eigen::Vector3d::Zero();
    if (!options_.slanted) {
      step(0) = -normals.je(0) / jj(0, 0);
    } else {
      step = -jj.ldlt().solve(normals.je);
      if (!step.allFinite()) return std::nullopt;
    }
    p += step;
    out.iterations = iteration + 1;
    if (!(std::abs(p(0) - start) <= options_.max_correction_px)) return std::nullopt;
    if (!(std::abs(p(1)) <= options_.max_slope) || !(std::abs(p(2)) <= options_.max_slope)) return std::nullopt;
    if (std::abs(step(0)) < options_.tolerance_px && std::abs(step(1)) * h < options_.tolerance_px &&
        std::abs(step(2)) * h < options_.tolerance_px) {
      break;
    }
  }
  out.u_px = u_image + 0.5 * p(0);
  out.disparity_px = d_int + p(0);
  out.slope_u = p(1);
  out.slope_v = p(2);
  return out;
}

}  // namespace aar
