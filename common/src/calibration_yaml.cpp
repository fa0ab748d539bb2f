#include "aar/calibration_yaml.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <vector>

#include "aar/error.h"

namespace aar {
namespace {

constexpr int kMaxMatrixSide = 64;  // calibration matrices are at most 4x4 (1x14 distortion)

struct Line {
  size_t number = 0;  // 1-based
  std::string_view text;
};

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
  return s;
}

bool IsKeyChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.'; }

// Splits `text` into lines, dropping blank and comment lines.
std::vector<Line> SignificantLines(std::string_view text) {
  std::vector<Line> lines;
  size_t number = 0;
  while (!text.empty()) {
    ++number;
    const size_t newline = text.find('\n');
    std::string_view line = text.substr(0, newline);
    text.remove_prefix(newline == std::string_view::npos ? text.size() : newline + 1);
    const std::string_view trimmed = Trim(line);
    if (trimmed.empty() || trimmed.front() == '#') continue;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    lines.push_back({number, line});
  }
  return lines;
}

double ParseNumber(std::string_view token, const std::string& at) {
  token = Trim(token);
  if (token == ".Inf" || token == ".inf" || token == "+.Inf") return std::numeric_limits<double>::infinity();
  if (token == "-.Inf" || token == "-.inf") return -std::numeric_limits<double>::infinity();
  if (token == ".NaN" || token == ".nan" || token == ".Nan") return std::numeric_limits<double>::quiet_NaN();
  const char* begin = token.data();
  const char* end = token.data() + token.size();
  if (begin != end && *begin == '+') ++begin;
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  if (begin == end || ec != std::errc() || ptr != end) {
    throw Error(at + ": '" + std::string(token) + "' is not a number");
  }
  return value;
}

// Reads a flow sequence "[ a, b, ... ]" that starts in `first` (after the
// key) and may continue over the following lines; advances `next`.
std::vector<double> ParseFlowSequence(std::string_view first, const std::vector<Line>& lines, size_t& next,
                                      const std::string& where, size_t first_number) {
  std::string body(Trim(first));
  size_t last_number = first_number;
  // Only the appended line is searched for ']': linear in the file size.
  for (bool closed = body.find(']') != std::string::npos; !closed; ++next) {
    if (next >= lines.size()) throw Error(where + ":" + std::to_string(first_number) + ": '[' without ']'");
    const std::string_view line = Trim(lines[next].text);
    closed = line.find(']') != std::string_view::npos;
    body += ' ';
    body += line;
    last_number = lines[next].number;
  }
  const std::string at = where + ":" + std::to_string(last_number);
  const size_t close = body.find(']');
  if (body.front() != '[' || !Trim(std::string_view(body).substr(close + 1)).empty() ||
      body.find('[', 1) != std::string::npos) {
    throw Error(at + ": malformed sequence (expected [ n, n, ... ])");
  }
  std::vector<double> values;
  std::string_view items = std::string_view(body).substr(1, close - 1);
  if (Trim(items).empty()) return values;
  while (true) {
    const size_t comma = items.find(',');
    values.push_back(ParseNumber(items.substr(0, comma), at));
    if (comma == std::string_view::npos) break;
    items.remove_prefix(comma + 1);
  }
  return values;
}

int ParseSide(std::string_view value, const char* name, const std::string& at) {
  const double v = ParseNumber(value, at);
  if (!(v >= 1 && v <= kMaxMatrixSide) || v != std::floor(v)) {
    throw Error(at + ": " + name + " must be an integer from 1 to " + std::to_string(kMaxMatrixSide));
  }
  return static_cast<int>(v);
}

// The indented body of a !!opencv-matrix node.
cv::Mat ParseMatrix(const std::vector<Line>& lines, size_t& next, const std::string& where, size_t key_line) {
  int rows = 0, cols = 0;
  std::string dt;
  std::vector<double> data;
  bool has_data = false;
  while (next < lines.size() && !lines[next].text.empty() && (lines[next].text[0] == ' ')) {
    const Line& line = lines[next++];
    const std::string at = where + ":" + std::to_string(line.number);
    const std::string_view text = Trim(line.text);
    const size_t colon = text.find(':');
    if (colon == std::string_view::npos) throw Error(at + ": expected 'name: value' inside the matrix");
    const std::string_view name = text.substr(0, colon);
    const std::string_view value = Trim(text.substr(colon + 1));
    if (name == "rows" && rows == 0) {
      rows = ParseSide(value, "rows", at);
    } else if (name == "cols" && cols == 0) {
      cols = ParseSide(value, "cols", at);
    } else if (name == "dt" && dt.empty()) {
      dt = std::string(value);
      if (dt != "d" && dt != "f" && dt != "i" && dt != "u" && dt != "c" && dt != "w" && dt != "s") {
        throw Error(at + ": dt '" + dt + "' is not a single-channel element type (d, f, i, s, w, u, c)");
      }
    } else if (name == "data" && !has_data) {
      data = ParseFlowSequence(value, lines, next, where, line.number);
      has_data = true;
    } else {
      throw Error(at + ": unexpected or repeated '" + std::string(name) + "' inside the matrix");
    }
  }
  const std::string at = where + ":" + std::to_string(key_line);
  if (rows == 0 || cols == 0 || dt.empty() || !has_data) throw Error(at + ": matrix needs rows, cols, dt and data");
  if (data.size() != static_cast<size_t>(rows) * static_cast<size_t>(cols)) {
    throw Error(at + ": matrix is " + std::to_string(rows) + "x" + std::to_string(cols) + " but data holds " +
                std::to_string(data.size()) + " values");
  }
  cv::Mat m(rows, cols, CV_64F);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) m.at<double>(r, c) = data[static_cast<size_t>(r * cols + c)];
  }
  return m;
}

}  // namespace

std::map<std::string, cv::Mat> ParseOpenCvYaml(std::string_view text, const std::string& where) {
  if (text.size() > kMaxCalibrationYamlBytes) {
    throw Error(where + ": " + std::to_string(text.size()) + " bytes, larger than a calibration file can be (" +
                std::to_string(kMaxCalibrationYamlBytes) + ")");
  }
  if (text.find('\0') != std::string_view::npos) throw Error(where + ": not a text file (holds NUL bytes)");
  const std::vector<Line> lines = SignificantLines(text);
  std::map<std::string, cv::Mat> nodes;
  size_t next = 0;
  if (next < lines.size() && lines[next].text.starts_with("%YAML")) ++next;
  if (next < lines.size() && Trim(lines[next].text) == "---") ++next;
  while (next < lines.size()) {
    const Line& line = lines[next++];
    const std::string at = where + ":" + std::to_string(line.number);
    const std::string_view text_line = line.text;
    size_t key_end = 0;
    while (key_end < text_line.size() && IsKeyChar(text_line[key_end])) ++key_end;
    if (key_end == 0 || key_end >= text_line.size() || text_line[key_end] != ':') {
      throw Error(at + ": expected 'name: value' at the start of the line (OpenCV FileStorage YAML)");
    }
    const std::string key(text_line.substr(0, key_end));
    const std::string_view value = Trim(text_line.substr(key_end + 1));
    if (nodes.contains(key)) throw Error(at + ": node '" + key + "' appears twice");
    if (value == "!!opencv-matrix" || value == "!<tag:yaml.org,2002:opencv-matrix>") {
      nodes[key] = ParseMatrix(lines, next, where, line.number);
    } else if (!value.empty() && value.front() == '[') {
      const std::vector<double> values = ParseFlowSequence(value, lines, next, where, line.number);
      if (values.size() > static_cast<size_t>(kMaxMatrixSide)) throw Error(at + ": sequence '" + key + "' too long");
      cv::Mat m(1, static_cast<int>(values.size()), CV_64F);
      for (size_t i = 0; i < values.size(); ++i) m.at<double>(0, static_cast<int>(i)) = values[i];
      nodes[key] = values.empty() ? cv::Mat() : m;
    } else if (value.size() >= 2 && (value.front() == '"' || value.front() == '\'') && value.back() == value.front()) {
      continue;  // a string: not needed by any reader
    } else if (!value.empty()) {
      nodes[key] = cv::Mat(1, 1, CV_64F, cv::Scalar(ParseNumber(value, at)));
    } else {
      throw Error(at + ": node '" + key + "' has no value (nested mappings are not supported)");
    }
  }
  return nodes;
}

}  // namespace aar
