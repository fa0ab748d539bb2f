#include "aar/renderer/optical_blur.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace aar {
namespace {

std::vector<double> GaussianKernel(double sigma_px) {
  const int radius = GaussianKernelRadius(sigma_px);
  std::vector<double> kernel(2 * radius + 1);
  double sum = 0.0;
  for (int i = -radius; i <= radius; ++i) {
    kernel[i + radius] = std::exp(-0.5 * i * i / (sigma_px * sigma_px));
    sum += kernel[i + radius];
  }
  for (double& k : kernel) k /= sum;
  return kernel;
}

// One pass along rows (step 3, the next pixel of a row) or columns (step 3 *
// width). Each output value sums kernel[k] * in[tap k] for k = 0 .. 2 radius
// in that order, in double, with taps beyond the border clamped to it; the
// interior skips the clamping, which changes no tap and so no bit.
void Convolve(const std::vector<float>& in, std::vector<float>& out, int width, int height, bool along_rows,
              const std::vector<double>& kernel) {
  const int radius = static_cast<int>(kernel.size() / 2);
  const int length = along_rows ? width : height;
  const ptrdiff_t step = along_rows ? 3 : 3 * static_cast<ptrdiff_t>(width);  // between taps, in floats
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const int at = along_rows ? x : y;
      const size_t centre = 3 * (static_cast<size_t>(y) * width + x);
      if (at >= radius && at + radius < length) {
        const float* first = &in[centre] - radius * step;
        for (int c = 0; c < 3; ++c) {
          double sum = 0.0;
          for (size_t k = 0; k < kernel.size(); ++k) sum += kernel[k] * first[static_cast<ptrdiff_t>(k) * step + c];
          out[centre + c] = static_cast<float>(sum);
        }
        continue;
      }
      for (int c = 0; c < 3; ++c) {
        double sum = 0.0;
        for (int i = -radius; i <= radius; ++i) {
          const int p = std::clamp(at + i, 0, length - 1);
          const size_t index = along_rows ? (static_cast<size_t>(y) * width + p) : (static_cast<size_t>(p) * width + x);
          sum += kernel[i + radius] * in[3 * index + c];
        }
        out[centre + c] = static_cast<float>(sum);
      }
    }
  }
}

}  // namespace

int GaussianKernelRadius(double sigma_px) { return static_cast<int>(std::ceil(3.0 * sigma_px)); }

LinearImage GaussianBlur(const LinearImage& image, double sigma_px) {
  if (sigma_px <= 0.0) return image;
  const std::vector<double> kernel = GaussianKernel(sigma_px);
  LinearImage rows = image;
  Convolve(image.rgb, rows.rgb, image.width, image.height, true, kernel);
  LinearImage out = image;
  Convolve(rows.rgb, out.rgb, image.width, image.height, false, kernel);
  return out;
}

}  // namespace aar
