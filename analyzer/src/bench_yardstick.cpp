#include "aar/analyzer/bench_yardstick.h"

#include <chrono>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>

#include "aar/analyzer/dataset_image.h"

namespace aar {

double TimeStereoBmYardstick(const OpenedDataset& dataset, const Rectifier& rectifier, size_t index) {
  cv::Ptr<cv::StereoBM> bm = cv::StereoBM::create(48, 9);
  bm->setSpeckleWindowSize(100);
  bm->setSpeckleRange(32);  // StereoBM's speckle range is in its output's units, 1/16 px: 2 px
  const FrameSidecar sidecar = dataset.Sidecar("frame", index);
  const cv::Mat left = ReadListedImage(dataset, sidecar.files.at("left"), cv::IMREAD_COLOR, "image");
  const cv::Mat right = ReadListedImage(dataset, sidecar.files.at("right"), cv::IMREAD_COLOR, "image");
  cv::Mat rect_left, rect_right, disparity;
  rectifier.Rectify(left, right, rect_left, rect_right);
  const auto start = std::chrono::steady_clock::now();
  bm->compute(rect_left, rect_right, disparity);
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace aar
