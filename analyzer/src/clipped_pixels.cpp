#include "aar/analyzer/clipped_pixels.h"

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "aar/error.h"

namespace aar {

void ClippedPixelOptions::Check() const {
  if (clip_level < 1 || clip_level > 255) throw Error("clipped pixels: clip_level must be in [1, 255]");
  if (radius_px < 0 || radius_px > 64) throw Error("clipped pixels: radius_px must be in [0, 64]");
}

namespace {

// Pixels within `radius_px` of a pixel >= clip_level (255), else 0.
cv::Mat NearClipped(const cv::Mat& gray, const ClippedPixelOptions& options) {
  cv::Mat clipped = gray >= options.clip_level, near;
  const int size = 2 * options.radius_px + 1;
  cv::dilate(clipped, near, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(size, size)), cv::Point(-1, -1), 1,
             cv::BORDER_CONSTANT, cv::Scalar(0));
  return near;
}

}  // namespace

size_t RemoveClippedMatches(cv::Mat& disparity16, int invalid_value16, const cv::Mat& rect_left,
                            const cv::Mat& rect_right, const ClippedPixelOptions& options) {
  options.Check();
  if (disparity16.type() != CV_16SC1) throw Error("clipped pixels: disparity must be CV_16S (disparity * 16)");
  if (rect_left.type() != CV_8UC1 || rect_right.type() != CV_8UC1 || rect_left.size() != disparity16.size() ||
      rect_right.size() != disparity16.size()) {
    throw Error("clipped pixels: the rectified images must be 8-bit gray, the disparity map's size");
  }
  const cv::Mat near_left = NearClipped(rect_left, options), near_right = NearClipped(rect_right, options);
  size_t removed = 0;
  for (int v = 0; v < disparity16.rows; ++v) {
    short* row = disparity16.ptr<short>(v);
    const unsigned char* left = near_left.ptr<unsigned char>(v);
    const unsigned char* right = near_right.ptr<unsigned char>(v);
    for (int u = 0; u < disparity16.cols; ++u) {
      if (row[u] <= invalid_value16) continue;
      const long matched = u - std::lround(row[u] / 16.0);
      if (left[u] != 0 || (matched >= 0 && matched < disparity16.cols && right[matched] != 0)) {
        row[u] = static_cast<short>(invalid_value16);
        ++removed;
      }
    }
  }
  return removed;
}

}  // namespace aar
