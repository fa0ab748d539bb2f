#pragma once
// A strict reader of the OpenCV FileStorage YAML subset that calibration files
// use (docs/dataset-format.md), written without OpenCV's parser: OpenCV 4.6's
// FileStorage crashes or hangs on some small malformed files, so calibration
// files from outside are never handed to it.
//
// Accepted, one construct per top-level key (column 0):
//   %YAML:1.0 / ---          optional directive and document start
//   # comment                ignored, as are blank lines
//   key: 1.5                 a number (stored as a 1x1 matrix)
//   key: "text"              a quoted string (ignored; OpenCV samples write dates)
//   key: [ 1024, 768 ]       a flow sequence of numbers (1xN), may span lines
//   key: !!opencv-matrix     followed by indented rows:, cols:, dt:, data: [ ... ]

#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <string_view>

namespace aar {

/// Largest calibration file read [bytes]; a calibration is about 2 KiB.
inline constexpr size_t kMaxCalibrationYamlBytes = 1 << 20;

/// The numeric nodes of a FileStorage YAML text: name -> CV_64F matrix
/// (rows x cols for !!opencv-matrix, 1xN for sequences, 1x1 for numbers).
/// Throws aar::Error "<where>:<line>: <reason>" on anything outside the
/// subset, a duplicate key, a number that does not parse, or a matrix whose
/// data count differs from rows x cols. Non-finite values are kept (callers
/// decide).
std::map<std::string, cv::Mat> ParseOpenCvYaml(std::string_view text, const std::string& where);

}  // namespace aar
