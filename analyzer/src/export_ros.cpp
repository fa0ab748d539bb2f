#include "aar/analyzer/export_ros.h"

#include "aar/error.h"
#include "aar/file_io.h"

namespace aar {
namespace {

std::string MatrixYaml(const std::string& name, const cv::Mat& m) {
  cv::Mat m64;
  m.convertTo(m64, CV_64F);
  std::string text =
      name + ":\n  rows: " + std::to_string(m64.rows) + "\n  cols: " + std::to_string(m64.cols) + "\n  data: [";
  for (int r = 0; r < m64.rows; ++r) {
    for (int c = 0; c < m64.cols; ++c) text += (r || c ? ", " : "") + ShortestDecimal(m64.at<double>(r, c));
  }
  return text + "]\n";
}

}  // namespace

std::string CameraInfoYaml(const StereoCalibration& calibration, const std::string& camera) {
  const bool left = camera == "left";
  return "image_width: " + std::to_string(calibration.image_size.width) +
         "\nimage_height: " + std::to_string(calibration.image_size.height) + "\ncamera_name: " + camera + "\n" +
         MatrixYaml("camera_matrix", left ? calibration.M1 : calibration.M2) + "distortion_model: plumb_bob\n" +
         MatrixYaml("distortion_coefficients", left ? calibration.D1 : calibration.D2) +
         MatrixYaml("rectification_matrix", left ? calibration.R1 : calibration.R2) +
         MatrixYaml("projection_matrix", left ? calibration.P1 : calibration.P2);
}

ExportResult ExportRos(const ExportOptions& options) {
  const ExportSource source = ReadExportSource(options);
  const StereoCalibration calibration = ReadIdealCalibration(source);
  ExportResult result;
  result.frames = source.frames.size();
  for (const char* camera : {"left", "right"}) {
    WriteExportFile(options.out, std::string(camera) + ".yaml", CameraInfoYaml(calibration, camera), result);
  }
  return result;
}

}  // namespace aar
