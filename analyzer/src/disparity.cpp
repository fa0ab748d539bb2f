#include "aar/analyzer/disparity.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "aar/error.h"

namespace aar {
namespace {

cv::Ptr<cv::StereoMatcher> MakeMatcher(const DisparityOptions& o) {
  if (o.algorithm == DisparityAlgorithm::kBlockMatching) {
    cv::Ptr<cv::StereoBM> bm = cv::StereoBM::create(o.num_disparities, o.block_size);
    bm->setMinDisparity(o.min_disparity);
    bm->setPreFilterType(cv::StereoBM::PREFILTER_XSOBEL);
    bm->setPreFilterCap(o.pre_filter_cap);
    bm->setTextureThreshold(o.texture_threshold);
    bm->setUniquenessRatio(o.uniqueness_ratio);
    bm->setDisp12MaxDiff(o.disp12_max_diff);
    bm->setSpeckleWindowSize(0);  // filtered below with explicit units
    bm->setSpeckleRange(0);
    return bm;
  }
  return cv::StereoSGBM::create(o.min_disparity, o.num_disparities, o.block_size, o.sgbm_p1, o.sgbm_p2,
                                o.disp12_max_diff, o.pre_filter_cap, o.uniqueness_ratio, 0, 0,
                                cv::StereoSGBM::MODE_SGBM);
}

}  // namespace

double MatcherRoundingBiasPx(DisparityAlgorithm algorithm) {
  return algorithm == DisparityAlgorithm::kBlockMatching ? 15.0 / 512.0 : 0.0;
}

void DisparityOptions::Check() const {
  const auto fail = [](const std::string& message) { throw Error("disparity options: " + message); };
  if (num_disparities <= 0 || num_disparities % 16 != 0 || num_disparities > 4096) {
    fail("num_disparities (--num-disparities) must be a multiple of 16 from 16 to 4096");
  }
  if (block_size < 5 || block_size > 255 || block_size % 2 == 0) {
    if (algorithm == DisparityAlgorithm::kBlockMatching || block_size < 1 || block_size % 2 == 0) {
      fail("block_size must be odd (5..255 for block matching)");
    }
  }
  if (pre_filter_cap < 1 || pre_filter_cap > 63) fail("pre_filter_cap must be in 1..63");
  if (texture_threshold < 0) fail("texture_threshold must be non-negative");
  if (uniqueness_ratio < 0) fail("uniqueness_ratio must be non-negative");
  if (speckle_window_size < 0) fail("speckle_window_size must be non-negative");
  if (!(speckle_range_px >= 0)) fail("speckle_range_px must be non-negative");
  if (std::isnan(background_disparity_px)) fail("background_disparity_px must be a number");
  if (sgbm_p1 < 0 || sgbm_p2 <= sgbm_p1) fail("SGBM needs 0 <= p1 < p2");
}

cv::Mat ToGrayscale(const cv::Mat& image, const std::string& name) {
  if (image.empty()) throw Error(name + ": empty image");
  if (image.depth() != CV_8U) throw Error(name + ": expected an 8-bit image");
  cv::Mat gray;
  switch (image.channels()) {
    case 1:
      return image;
    case 3:
      cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
      return gray;
    case 4:
      cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
      return gray;
    default:
      throw Error(name + ": expected 1, 3 or 4 channels");
  }
}

namespace {
constexpr int kSourceBlock = 32;  // [map pixels]
}  // namespace

Rectifier::SourceBlocks Rectifier::BlocksOf(const cv::Mat& map1, cv::Size image_size) {
  SourceBlocks blocks;
  blocks.block_columns = (map1.cols + kSourceBlock - 1) / kSourceBlock;
  const int block_rows = (map1.rows + kSourceBlock - 1) / kSourceBlock;
  const cv::Rect image(0, 0, image_size.width, image_size.height);
  for (int by = 0; by < block_rows; ++by) {
    for (int bx = 0; bx < blocks.block_columns; ++bx) {
      constexpr int kMax = std::numeric_limits<int>::max(), kMin = std::numeric_limits<int>::min();
      int x0 = kMax, y0 = kMax, x1 = kMin, y1 = kMin;
      for (int y = by * kSourceBlock; y < std::min(map1.rows, (by + 1) * kSourceBlock); ++y) {
        const cv::Vec2s* row = map1.ptr<cv::Vec2s>(y);
        for (int x = bx * kSourceBlock; x < std::min(map1.cols, (bx + 1) * kSourceBlock); ++x) {
          x0 = std::min<int>(x0, row[x][0]);
          x1 = std::max<int>(x1, row[x][0]);
          y0 = std::min<int>(y0, row[x][1]);
          y1 = std::max<int>(y1, row[x][1]);
        }
      }
      // Bilinear sampling reads (x, y) to (x + 1, y + 1).
      blocks.reads.push_back(cv::Rect(cv::Point(x0, y0), cv::Point(x1 + 2, y1 + 2)) & image);
    }
  }
  return blocks;
}

cv::Rect Rectifier::SourceBlocks::Needed(const cv::Rect& region) const {
  cv::Rect needed;
  for (int by = region.y / kSourceBlock; by <= (region.br().y - 1) / kSourceBlock; ++by) {
    for (int bx = region.x / kSourceBlock; bx <= (region.br().x - 1) / kSourceBlock; ++bx) {
      const cv::Rect& reads = this->reads[static_cast<size_t>(by * block_columns + bx)];
      needed = needed.area() > 0 ? needed | reads : reads;
    }
  }
  return needed;
}

Rectifier::Rectifier(const StereoCalibration& c) : image_size_(c.image_size) {
  if (image_size_.width <= 0 || image_size_.height <= 0) throw Error("rectifier: calibration has no image size");
  cv::initUndistortRectifyMap(c.M1, c.D1, c.R1, c.P1, image_size_, CV_16SC2, left_map1_, left_map2_);
  cv::initUndistortRectifyMap(c.M2, c.D2, c.R2, c.P2, image_size_, CV_16SC2, right_map1_, right_map2_);
  left_blocks_ = BlocksOf(left_map1_, image_size_);
  right_blocks_ = BlocksOf(right_map1_, image_size_);
}

void Rectifier::Rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat& rect_left_gray,
                        cv::Mat& rect_right_gray) const {
  Rectify(left, right, rect_left_gray, rect_right_gray, cv::Rect());
}

void Rectifier::Rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat& rect_left_gray, cv::Mat& rect_right_gray,
                        const cv::Rect& region) const {
  if (left.size() != image_size_ || right.size() != image_size_) {
    throw Error("rectifier: images are " + std::to_string(left.cols) + "x" + std::to_string(left.rows) + " and " +
                std::to_string(right.cols) + "x" + std::to_string(right.rows) + ", calibration is for " +
                std::to_string(image_size_.width) + "x" + std::to_string(image_size_.height));
  }
  const cv::Rect all(0, 0, image_size_.width, image_size_.height);
  const cv::Rect r = region.area() > 0 ? region & all : all;
  // A colour input is converted to grey where the region's maps read it
  // only (the rest of the grey image is allocated, never read).
  const auto grey_where_read = [&](const cv::Mat& image, const SourceBlocks& blocks) {
    if (r == all || image.depth() != CV_8U || (image.channels() != 3 && image.channels() != 4)) {
      return ToGrayscale(image);
    }
    cv::Mat grey(image.size(), CV_8UC1);
    const cv::Rect needed = blocks.Needed(r);
    if (needed.area() > 0) {
      cv::Mat part = grey(needed);  // written in place: cvtColor keeps a destination of the right size and type
      cv::cvtColor(image(needed), part, image.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
    }
    return grey;
  };
  cv::remap(grey_where_read(left, left_blocks_), rect_left_gray, left_map1_(r), left_map2_(r), cv::INTER_LINEAR,
            cv::BORDER_CONSTANT);
  cv::remap(grey_where_read(right, right_blocks_), rect_right_gray, right_map1_(r), right_map2_(r), cv::INTER_LINEAR,
            cv::BORDER_CONSTANT);
}

DisparityMap ComputeDisparity(const cv::Mat& rect_left_gray, const cv::Mat& rect_right_gray,
                              const DisparityOptions& options) {
  options.Check();
  if (rect_left_gray.type() != CV_8UC1 || rect_right_gray.type() != CV_8UC1) {
    throw Error("disparity: rectified images must be 8-bit grayscale");
  }
  if (rect_left_gray.size() != rect_right_gray.size()) throw Error("disparity: rectified images differ in size");

  DisparityMap map;
  map.invalid_value16 = options.InvalidValue16();
  MakeMatcher(options)->compute(rect_left_gray, rect_right_gray, map.disparity16);
  CV_Assert(map.disparity16.type() == CV_16SC1);
  if (options.background_disparity_px >= 0.0) {
    const int background16 = static_cast<int>(std::floor(options.background_disparity_px * 16.0));
    const short invalid16 = static_cast<short>(map.invalid_value16);
    for (int v = 0; v < map.disparity16.rows; ++v) {
      short* row = map.disparity16.ptr<short>(v);
      for (int u = 0; u < map.disparity16.cols; ++u) {
        if (row[u] <= background16) row[u] = invalid16;
      }
    }
  }
  if (options.speckle_window_size > 0) {
    // Thesis 3.4: OpenCV's speckle filter, maxDiff in the map's 1/16 px units.
    const double max_diff16 = std::round(options.speckle_range_px * 16.0);
    cv::filterSpeckles(map.disparity16, map.invalid_value16, options.speckle_window_size, max_diff16);
  }
  return map;
}

}  // namespace aar
