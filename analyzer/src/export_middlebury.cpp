#include "aar/analyzer/export_middlebury.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "aar/analyzer/stereo_truth.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/stereo_calibration.h"

namespace aar {
namespace {

std::string CameraMatrixText(const cv::Mat& p) {
  std::string text = "[";
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) text += (c ? " " : "") + ShortestDecimal(p.at<double>(r, c));
    text += r < 2 ? "; " : "]";
  }
  return text;
}

// The depth roles of the views that have depth truth: left always, right with --depth-right.
struct View {
  const char* side;
  const char* disparity_name;
};
constexpr View kViews[] = {{"left", "disp0GT.pfm"}, {"right", "disp1GT.pfm"}};

}  // namespace

std::string EncodePfm(const cv::Mat& image) {
  CV_Assert(image.type() == CV_32FC1);
  std::string bytes = "Pf\n" + std::to_string(image.cols) + " " + std::to_string(image.rows) + "\n-1\n";
  const size_t row_bytes = static_cast<size_t>(image.cols) * sizeof(float);
  const size_t header = bytes.size();
  bytes.resize(header + row_bytes * static_cast<size_t>(image.rows));
  for (int y = 0; y < image.rows; ++y) {
    // Little-endian host (x86-64, arm64): the floats are copied as they are.
    std::memcpy(&bytes[header + row_bytes * static_cast<size_t>(image.rows - 1 - y)], image.ptr<float>(y), row_bytes);
  }
  return bytes;
}

cv::Mat DisparityFromDepth(const cv::Mat& depth_m, double focal_times_baseline_px_m) {
  cv::Mat disparity(depth_m.size(), CV_32FC1);
  for (int y = 0; y < depth_m.rows; ++y) {
    for (int x = 0; x < depth_m.cols; ++x) {
      const double z = depth_m.at<float>(y, x);
      disparity.at<float>(y, x) =
          z > 0.0 ? static_cast<float>(focal_times_baseline_px_m / z) : std::numeric_limits<float>::infinity();
    }
  }
  return disparity;
}

ExportResult ExportMiddlebury(const ExportOptions& options) {
  const ExportSource source = ReadExportSource(options);
  const StereoCalibration calibration = ReadIdealCalibration(source);
  cv::Mat r1, r2, p1, p2;
  calibration.R1.convertTo(r1, CV_64F);
  calibration.R2.convertTo(r2, CV_64F);
  calibration.P1.convertTo(p1, CV_64F);
  calibration.P2.convertTo(p2, CV_64F);
  const cv::Mat identity = cv::Mat::eye(3, 3, CV_64F);
  if (cv::norm(r1 - identity) > 1e-9 || cv::norm(r2 - identity) > 1e-9) {
    throw Error((options.dataset / kIdealCalibrationName).string() +
                ": the images are not rectified (R1, R2 are not the identity)");
  }
  if (cv::countNonZero(calibration.D1 != 0) > 0 || cv::countNonZero(calibration.D2 != 0) > 0) {
    throw Error((options.dataset / kIdealCalibrationName).string() +
                ": the images are not rectified (the cameras have lens distortion, D1/D2 not zero)");
  }
  const double f = p1.at<double>(0, 0);
  const double baseline_m = -p2.at<double>(0, 3) / p2.at<double>(0, 0);
  const double doffs = p2.at<double>(0, 2) - p1.at<double>(0, 2);

  // Every file is checked before the first one is written.
  for (const FrameSidecar& frame : source.frames) {
    for (const char* role : {"left", "right"}) ReadVerifiedFile(source, frame.files.at(role));
    for (const char* role : {"left_depth", "left_mask"})
      ReadVerifiedFile(source, RequireFile(source, frame, role, "--depth"));
    for (const char* role : {"right_depth", "right_mask"}) {
      if (frame.files.contains(role)) ReadVerifiedFile(source, frame.files.at(role));
    }
  }
  ExportResult result;
  result.frames = source.frames.size();
  size_t without_right = 0;
  for (const FrameSidecar& frame : source.frames) {
    const std::string dir = FrameStem(frame.index) + "/";
    WriteExportFile(options.out, dir + "im0.png", ReadVerifiedFile(source, frame.files.at("left")), result);
    WriteExportFile(options.out, dir + "im1.png", ReadVerifiedFile(source, frame.files.at("right")), result);
    double vmin = std::numeric_limits<double>::infinity(), vmax = 0.0;
    for (const View& view : kViews) {
      const std::string side = view.side;
      if (!frame.files.contains(side + "_depth") || !frame.files.contains(side + "_mask")) {
        ++without_right;
        continue;
      }
      const DepthTruth truth = ReadDepthTruth(options.dataset / frame.files.at(side + "_depth").path,
                                              options.dataset / frame.files.at(side + "_mask").path);
      const cv::Mat disparity = DisparityFromDepth(truth.depth_m, f * baseline_m);
      for (auto it = disparity.begin<float>(); it != disparity.end<float>(); ++it) {
        if (std::isfinite(*it)) {
          vmin = std::min(vmin, static_cast<double>(*it));
          vmax = std::max(vmax, static_cast<double>(*it));
        }
      }
      WriteExportFile(options.out, dir + view.disparity_name, EncodePfm(disparity), result);
    }
    if (!std::isfinite(vmin)) vmin = vmax = 0.0;
    // ndisp: a bound on the disparity levels a matcher must search (multiple of 16).
    const int ndisp = static_cast<int>(std::ceil((std::ceil(vmax) + 1.0) / 16.0)) * 16;
    const std::string calib =
        "cam0=" + CameraMatrixText(p1) + "\ncam1=" + CameraMatrixText(p2) + "\ndoffs=" + ShortestDecimal(doffs) +
        "\nbaseline=" + ShortestDecimal(baseline_m * 1000.0) +
        "\nwidth=" + std::to_string(calibration.image_size.width) +
        "\nheight=" + std::to_string(calibration.image_size.height) + "\nndisp=" + std::to_string(ndisp) +
        "\nisint=0\nvmin=" + std::to_string(static_cast<int>(std::floor(vmin))) +
        "\nvmax=" + std::to_string(static_cast<int>(std::ceil(vmax))) + "\n";
    WriteExportFile(options.out, dir + "calib.txt", calib, result);
  }
  if (without_right > 0) {
    result.notes.push_back("no disp1GT.pfm for " + std::to_string(without_right) +
                           " frames: the dataset has no right-camera depth (render with --depth-right)");
  }
  return result;
}

}  // namespace aar
