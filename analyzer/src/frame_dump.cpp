#include "aar/analyzer/frame_dump.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "aar/analyzer/ply.h"
#include "aar/dataset.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/text.h"

namespace aar {
namespace {

void WritePng(const std::filesystem::path& path, const cv::Mat& image) {
  std::vector<uint8_t> bytes;
  if (!cv::imencode(".png", image, bytes, {cv::IMWRITE_PNG_COMPRESSION, 3})) {
    throw Error(path.string() + ": PNG encoding failed");
  }
  WriteFileAtomic(path, std::string(bytes.begin(), bytes.end()));
}

// Pixel of a tanker-frame point in the left image; nullopt behind the camera.
std::optional<cv::Point2d> Project(const DumpProjection& p, const Eigen::Vector3d& point_in_tanker) {
  const Eigen::Vector3d in_left = p.left_from_tanker * point_in_tanker;
  if (!(in_left.z() > 0.0)) return std::nullopt;
  const Eigen::Vector2d x = Distort(p.left_distortion, Eigen::Vector2d(in_left.x(), in_left.y()) / in_left.z());
  const Eigen::Vector3d uv = p.left_camera_matrix * Eigen::Vector3d(x.x(), x.y(), 1.0);
  return cv::Point2d(uv.x(), uv.y());
}

void DrawCross(cv::Mat& image, const std::optional<cv::Point2d>& at, const cv::Scalar& colour) {
  if (!at) return;
  const cv::Point c(static_cast<int>(std::lround(at->x)), static_cast<int>(std::lround(at->y)));
  cv::line(image, c - cv::Point(8, 0), c + cv::Point(8, 0), colour, 2);
  cv::line(image, c - cv::Point(0, 8), c + cv::Point(0, 8), colour, 2);
}

}  // namespace

cv::Mat ColourDisparity(const FrameDump& dump, const cv::Size& image_size) {
  // The colour range: the smallest to the largest disparity of the map.
  int lo = std::numeric_limits<int>::max(), hi = std::numeric_limits<int>::min();
  for (int y = 0; y < dump.disparity16.rows; ++y) {
    for (int x = 0; x < dump.disparity16.cols; ++x) {
      const int d = dump.disparity16.at<int16_t>(y, x);
      if (d == dump.invalid_value16 || d < 0) continue;
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
  }
  cv::Mat grey(image_size, CV_8UC1, cv::Scalar(0));
  cv::Mat valid(image_size, CV_8UC1, cv::Scalar(0));
  const double scale = hi > lo ? 255.0 / (hi - lo) : 0.0;
  for (int y = 0; y < dump.disparity16.rows; ++y) {
    for (int x = 0; x < dump.disparity16.cols; ++x) {
      const int d = dump.disparity16.at<int16_t>(y, x);
      const cv::Point p(x + dump.region.x, y + dump.region.y);
      if (d == dump.invalid_value16 || d < 0 || p.x >= image_size.width || p.y >= image_size.height) continue;
      grey.at<uint8_t>(p) = cv::saturate_cast<uint8_t>((d - lo) * scale);
      valid.at<uint8_t>(p) = 255;
    }
  }
  cv::Mat colour;
  cv::applyColorMap(grey, colour, cv::COLORMAP_TURBO);
  cv::Mat out(image_size, CV_8UC3, cv::Scalar(0, 0, 0));
  colour.copyTo(out, valid);
  return out;
}

cv::Mat OverlayModel(const FrameDump& dump, const DumpProjection& projection) {
  if (!dump.tanker_from_receiver || dump.left_bgr.empty()) return cv::Mat();
  cv::Mat image = dump.left_bgr.clone();
  const cv::Rect inside(0, 0, image.cols, image.rows);
  for (const Eigen::Vector3d& m : projection.model_points_in_receiver) {
    const std::optional<cv::Point2d> uv = Project(projection, *dump.tanker_from_receiver * m);
    if (!uv) continue;
    const cv::Point p(static_cast<int>(std::lround(uv->x)), static_cast<int>(std::lround(uv->y)));
    if (inside.contains(p)) image.at<cv::Vec3b>(p) = cv::Vec3b(0, 255, 0);
  }
  DrawCross(image, Project(projection, dump.tanker_from_receiver_truth.translation()), cv::Scalar(0, 0, 255));
  DrawCross(image, Project(projection, dump.tanker_from_receiver->translation()), cv::Scalar(0, 255, 0));
  return image;
}

void WriteFrameDump(const std::filesystem::path& dir, size_t index, const FrameDump& dump,
                    const DumpProjection& projection) {
  EnsureWritableDirectory(dir);
  const std::string stem = FrameStem(index);
  if (!dump.disparity16.empty()) WritePng(dir / (stem + "_disparity.png"), ColourDisparity(dump, dump.left_bgr.size()));
  if (!dump.sensed_in_tanker.empty()) {
    WritePly(dir / (stem + "_sensed.ply"), dump.sensed_in_tanker,
             {"aar-analyze frame " + std::to_string(index) + ": sensed cloud, tanker frame, metres"});
  }
  if (!dump.pixels.empty()) {
    std::string csv = "u_px,v_px,disparity_px,true_disparity_px\n";
    for (size_t k = 0; k < dump.pixels.size(); ++k) {
      const Eigen::Vector3d& p = dump.pixels[k];
      const bool has_truth = k < dump.true_disparity_px.size() && std::isfinite(dump.true_disparity_px[k]);
      csv += FormatFixed(p.x(), 4) + "," + FormatFixed(p.y(), 4) + "," + FormatFixed(p.z(), 6) + "," +
             (has_truth ? FormatFixed(dump.true_disparity_px[k], 6) : std::string()) + "\n";
    }
    WriteFileAtomic(dir / (stem + "_points.csv"), csv);
  }
  if (dump.tanker_from_receiver) {
    std::vector<Eigen::Vector3d> model;
    model.reserve(projection.model_points_in_receiver.size());
    for (const Eigen::Vector3d& m : projection.model_points_in_receiver)
      model.push_back(*dump.tanker_from_receiver * m);
    WritePly(
        dir / (stem + "_model.ply"), model,
        {"aar-analyze frame " + std::to_string(index) + ": reference model at the estimate, tanker frame, metres"});
    WritePng(dir / (stem + "_overlay.png"), OverlayModel(dump, projection));
  }
}

}  // namespace aar
