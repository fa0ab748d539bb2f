#include "aar/flight_path.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "aar/error.h"
#include "aar/text.h"

namespace aar {

std::vector<FlightSample> ReadFlightPath(const std::filesystem::path& path) {
  std::ifstream file(path);
  if (!file) throw Error(path.string() + ": cannot open flight path");
  std::ostringstream text;
  text << file.rdbuf();
  return ParseFlightPath(text.str(), path.string());
}

std::vector<FlightSample> ParseFlightPath(const std::string& text, const std::string& name) {
  std::istringstream in(text);
  std::string line;
  if (!std::getline(in, line)) throw Error(name + ":1: empty file, expected header '" + kFlightPathHeader + "'");
  // A UTF-8 byte-order mark (spreadsheet exports) is not part of the header.
  if (line.starts_with("\xEF\xBB\xBF")) line.erase(0, 3);
  const bool with_boom = TrimCr(line) == kFlightPathBoomHeader;
  if (TrimCr(line) != kFlightPathHeader && !with_boom) {
    throw Error(name + ":1: wrong header '" + PrintableText(TrimCr(line)) + "', expected '" + kFlightPathHeader +
                "' or, with the boom, '" + kFlightPathBoomHeader + "'");
  }
  const size_t columns = with_boom ? 10 : 7;
  std::vector<FlightSample> samples;
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    line = TrimCr(line);
    if (line.empty()) continue;
    const std::vector<std::string> fields = SplitCsvLine(line);
    const std::string where = name + ":" + std::to_string(line_number);
    if (fields.size() != columns) {
      throw Error(where + ": expected " + std::to_string(columns) + " fields, found " + std::to_string(fields.size()));
    }
    static const char* kNames[] = {
        "time_s",          "x_m", "y_m", "z_m", "roll_deg", "pitch_deg", "yaw_deg", "boom_pitch_deg", "boom_roll_deg",
        "boom_extension_m"};
    double v[10];
    for (size_t i = 0; i < columns; ++i) v[i] = ParseFiniteDouble(fields[i], where + ": field " + kNames[i]);
    FlightSample s;
    s.time_s = v[0];
    s.tanker_from_receiver.translation_m = {v[1], v[2], v[3]};
    s.tanker_from_receiver.roll_deg = v[4];
    s.tanker_from_receiver.pitch_deg = v[5];
    s.tanker_from_receiver.yaw_deg = v[6];
    if (with_boom) {
      s.boom = BoomPose{v[7], v[8], v[9]};
      s.boom->Check(where);
    }
    samples.push_back(s);
  }
  if (samples.empty()) throw Error(name + ": flight path has no samples");
  return samples;
}

void CheckTimesIncrease(const std::vector<FlightSample>& path, const std::string& where) {
  for (size_t i = 1; i < path.size(); ++i) {
    if (!(path[i].time_s > path[i - 1].time_s)) {
      throw Error(where + ": time_s must increase from sample to sample, but sample " + std::to_string(i) + " (" +
                  FormatFixed(path[i].time_s, 3) + " s) follows sample " + std::to_string(i - 1) + " (" +
                  FormatFixed(path[i - 1].time_s, 3) + " s)");
    }
  }
}

Eigen::Isometry3d TankerFromReceiverAt(const std::vector<FlightSample>& path, double time_s) {
  if (path.size() == 1) return IsometryFromPose(path.front().tanker_from_receiver);
  const auto after =
      std::upper_bound(path.begin(), path.end(), time_s, [](double t, const FlightSample& s) { return t < s.time_s; });
  const size_t k1 = std::clamp<size_t>(static_cast<size_t>(after - path.begin()), 1, path.size() - 1);
  const FlightSample& s0 = path[k1 - 1];
  const FlightSample& s1 = path[k1];
  const double a = (time_s - s0.time_s) / (s1.time_s - s0.time_s);
  const Eigen::Isometry3d p0 = IsometryFromPose(s0.tanker_from_receiver);
  const Eigen::Isometry3d p1 = IsometryFromPose(s1.tanker_from_receiver);
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = (1.0 - a) * p0.translation() + a * p1.translation();
  p.linear() = Eigen::Quaterniond(p0.linear()).slerp(a, Eigen::Quaterniond(p1.linear())).toRotationMatrix();
  return p;
}

std::string FormatFlightPath(const std::vector<FlightSample>& samples) {
  std::ostringstream out;
  const bool with_boom = !samples.empty() && samples.front().boom.has_value();
  out << (with_boom ? kFlightPathBoomHeader : kFlightPathHeader) << '\n';
  for (const FlightSample& s : samples) {
    const Pose& p = s.tanker_from_receiver;
    out << FormatFixed(s.time_s, 3) << ',' << FormatFixed(p.translation_m.x(), 4) << ','
        << FormatFixed(p.translation_m.y(), 4) << ',' << FormatFixed(p.translation_m.z(), 4) << ','
        << FormatFixed(p.roll_deg, 4) << ',' << FormatFixed(p.pitch_deg, 4) << ',' << FormatFixed(p.yaw_deg, 4);
    if (s.boom.has_value() != with_boom) throw Error("flight path: the boom columns must be on every sample or none");
    if (with_boom) {
      out << ',' << FormatFixed(s.boom->pitch_deg, 4) << ',' << FormatFixed(s.boom->roll_deg, 4) << ','
          << FormatFixed(s.boom->extension_m, 4);
    }
    out << '\n';
  }
  return out.str();
}

namespace {

double Round(double value, double scale) { return std::round(value * scale) / scale; }

}  // namespace

FlightSample RoundToCsvPrecision(FlightSample s) {
  s.time_s = Round(s.time_s, 1e3);
  Pose& p = s.tanker_from_receiver;
  for (int i = 0; i < 3; ++i) p.translation_m(i) = Round(p.translation_m(i), 1e4);
  p.roll_deg = Round(p.roll_deg, 1e4);
  p.pitch_deg = Round(p.pitch_deg, 1e4);
  p.yaw_deg = Round(p.yaw_deg, 1e4);
  if (s.boom)
    *s.boom = BoomPose{Round(s.boom->pitch_deg, 1e4), Round(s.boom->roll_deg, 1e4), Round(s.boom->extension_m, 1e4)};
  return s;
}

}  // namespace aar
