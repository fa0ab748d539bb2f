#include "aar/analyzer/disparity_cleaning.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "aar/error.h"

namespace aar {

void HaloRemovalOptions::Check() const {
  if (radius_px < 0 || radius_px > 64) throw Error("halo removal: radius_px must be in [0, 64]");
  if (!(max_jump_px > 0.0)) throw Error("halo removal: max_jump_px must be positive");
}

int HaloRadiusPx(const DisparityOptions& options) { return options.block_size / 2 + 1; }

size_t RemoveHalo(cv::Mat& disparity16, int invalid_value16, const HaloRemovalOptions& options) {
  options.Check();
  if (disparity16.type() != CV_16SC1) throw Error("halo removal: disparity must be CV_16S (disparity * 16)");
  if (options.radius_px == 0 || disparity16.empty()) return 0;
  const int rows = disparity16.rows, cols = disparity16.cols;
  const int max_jump16 = static_cast<int>(std::floor(options.max_jump_px * 16.0));
  // Boundary: invalid pixels, and both pixels of a jump between valid neighbours.
  cv::Mat boundary(rows, cols, CV_8U, cv::Scalar(0));
  for (int v = 0; v < rows; ++v) {
    const short* row = disparity16.ptr<short>(v);
    const short* below = v + 1 < rows ? disparity16.ptr<short>(v + 1) : nullptr;
    unsigned char* b = boundary.ptr<unsigned char>(v);
    unsigned char* b_below = v + 1 < rows ? boundary.ptr<unsigned char>(v + 1) : nullptr;
    for (int u = 0; u < cols; ++u) {
      if (row[u] <= invalid_value16) {
        b[u] = 255;
        continue;
      }
      if (u + 1 < cols && row[u + 1] > invalid_value16 && std::abs(row[u + 1] - row[u]) > max_jump16) {
        b[u] = b[u + 1] = 255;
      }
      if (below != nullptr && below[u] > invalid_value16 && std::abs(below[u] - row[u]) > max_jump16) {
        b[u] = b_below[u] = 255;
      }
    }
  }
  cv::Mat near_boundary;
  const int size = 2 * options.radius_px + 1;
  cv::dilate(boundary, near_boundary, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(size, size)),
             cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  size_t removed = 0;
  for (int v = 0; v < rows; ++v) {
    short* row = disparity16.ptr<short>(v);
    const unsigned char* near = near_boundary.ptr<unsigned char>(v);
    for (int u = 0; u < cols; ++u) {
      if (row[u] > invalid_value16 && near[u] != 0) {
        row[u] = static_cast<short>(invalid_value16);
        ++removed;
      }
    }
  }
  return removed;
}

}  // namespace aar
