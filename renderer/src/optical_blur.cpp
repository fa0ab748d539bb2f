#include "aar/renderer/optical_blur.h"

#include <algorithm>
#include <cmath>
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

// One pass along rows (step 3, the next pixel of a row) or columns (step 3 * width).
void Convolve(const std::vector<float>& in, std::vector<float>& out, int width, int height, bool along_rows,
              const std::vector<double>& kernel) {
  const int radius = static_cast<int>(kernel.size() / 2);
  const int length = along_rows ? width : height;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const int at = along_rows ? x : y;
      for (int c = 0; c < 3; ++c) {
        double sum = 0.0;
        for (int i = -radius; i <= radius; ++i) {
          const int p = std::clamp(at + i, 0, length - 1);
          const size_t index = along_rows ? (static_cast<size_t>(y) * width + p) : (static_cast<size_t>(p) * width + x);
          sum += kernel[i + radius] * in[3 * index + c];
        }
        out[3 * (static_cast<size_t>(y) * width + x) + c] = static_cast<float>(sum);
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
