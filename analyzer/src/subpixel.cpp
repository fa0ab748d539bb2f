#include "aar/analyzer/subpixel.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "aar/error.h"

namespace aar {

void SubpixelOptions::Check() const {
  if (half_window_px < 1 || half_window_px > 32) throw Error("sub-pixel: half_window_px must be in [1, 32]");
  if (max_iterations < 1) throw Error("sub-pixel: max_iterations must be >= 1");
  if (!(tolerance_px > 0.0)) throw Error("sub-pixel: tolerance_px must be positive");
  if (!(max_correction_px > 0.0)) throw Error("sub-pixel: max_correction_px must be positive");
  if (!(min_gradient_energy >= 0.0)) throw Error("sub-pixel: min_gradient_energy must be >= 0");
  if (!(max_slope > 0.0 && max_slope <= 1.0)) throw Error("sub-pixel: max_slope must be in (0, 1]");
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
  row_ready_.assign(static_cast<size_t>(left8_.rows), 0);
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
  }
}

std::optional<RefinedDisparity> SubpixelRefiner::Refine(int u_image, int v_image, double disparity_px) const {
  const int u = u_image - origin_.x, v = v_image - origin_.y;
  const int h = options_.half_window_px;
  const double n = (2 * h + 1) * (2 * h + 1);
  const double d_int = std::round(disparity_px);
  const double start = disparity_px - d_int;
  // Both windows need their samples and the next column inside the image;
  // a slanted window's columns shift by up to max_slope * h more.
  const int margin = h + 2 + (options_.slanted ? static_cast<int>(std::ceil(options_.max_slope * h)) : 0);
  if (v - h < 0 || v + h >= left_.rows || u - margin < 0 || u + margin >= left_.cols || u - d_int - margin < 0 ||
      u - d_int + margin >= left_.cols) {
    return std::nullopt;
  }
  PrepareRows(v - h, v + h);
  // Parameters: delta (the centre's disparity minus d_int), and with a
  // slanted window its change per column and per row, so that sample (i, j)
  // (row, column offsets) is shifted by delta + a j + b i. One Gauss-Newton
  // step solves the zero-mean normal equations (the windows' brightness
  // offset is not a disparity) for all of them.
  Eigen::Vector3d p(start, 0.0, 0.0);
  RefinedDisparity out;
  const int max_iterations = options_.slanted ? 2 * options_.max_iterations : options_.max_iterations;
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    // One pass over the window gathers the sums of the normal equations.
    // The Jacobian of sample (i, j) is g (1, j, i), so per row only sums of
    // g, g j, g^2, g^2 j, g^2 j^2, e, e g and e g j are needed; the row
    // offset i multiplies them afterwards.
    double sum_e = 0.0, sum_g = 0.0, sum_gj = 0.0, sum_gi = 0.0;
    double sum_eg = 0.0, sum_egj = 0.0, sum_egi = 0.0;
    double s00 = 0.0, s01 = 0.0, s02 = 0.0, s11 = 0.0, s12 = 0.0, s22 = 0.0;
    for (int i = -h; i <= h; ++i) {
      const float* l = left_.ptr<float>(v + i);
      const float* r = right_.ptr<float>(v + i);
      // Sample (i, j) lies at xl = u + j + shift / 2 in the left image and
      // xr = u + j - d_int - shift / 2 in the right one.
      const double row_shift = p(0) + p(2) * i - p(1) * h;
      double xl = u - h + 0.5 * row_shift, xr = u - h - d_int - 0.5 * row_shift;
      const double step_l = 1.0 + 0.5 * p(1), step_r = 1.0 - 0.5 * p(1);
      float re = 0.0f, rg = 0.0f, rgj = 0.0f, rg2 = 0.0f, rg2j = 0.0f, rg2jj = 0.0f, reg = 0.0f, regj = 0.0f;
      for (int j = -h; j <= h; ++j, xl += step_l, xr += step_r) {
        // Interleaved (intensity, derivative) pairs: one index per image.
        const int il = static_cast<int>(xl), ir = static_cast<int>(xr);
        const float al = static_cast<float>(xl - il), ar = static_cast<float>(xr - ir);
        const float* pl = l + 2 * il;
        const float* pr = r + 2 * ir;
        // e = I_L(xl) - I_R(xr); de/d shift = (I_L'(xl) + I_R'(xr)) / 2.
        const float e = (pl[0] + al * (pl[2] - pl[0])) - (pr[0] + ar * (pr[2] - pr[0]));
        const float g = 0.5f * ((pl[1] + al * (pl[3] - pl[1])) + (pr[1] + ar * (pr[3] - pr[1])));
        const float fj = static_cast<float>(j), g2 = g * g, eg = e * g;
        re += e;
        rg += g;
        rgj += g * fj;
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
    const Eigen::Vector3d mean_j = Eigen::Vector3d(sum_g, sum_gj, sum_gi) / n;
    Eigen::Matrix3d jj;
    jj << s00, s01, s02, s01, s11, s12, s02, s12, s22;
    jj -= n * mean_j * mean_j.transpose();
    const Eigen::Vector3d je = Eigen::Vector3d(sum_eg, sum_egj, sum_egi) - sum_e * mean_j;
    if (!(jj(0, 0) >= options_.min_gradient_energy)) return std::nullopt;
    Eigen::Vector3d step = Eigen::Vector3d::Zero();
    if (!options_.slanted) {
      step(0) = -je(0) / jj(0, 0);
    } else {
      step = -jj.ldlt().solve(je);
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
