#include "aar/analyzer/export_tum.h"

#include <set>

#include "aar/analyzer/frame_results.h"
#include "aar/text.h"

namespace aar {

std::string TumLine(double time_s, const Pose& tanker_from_receiver) {
  const Eigen::Isometry3d pose = IsometryFromPose(tanker_from_receiver);
  const Eigen::Quaterniond q = UnitQuaternion(pose.linear());
  const Eigen::Vector3d& t = pose.translation();
  std::string line = FormatFixed(time_s, 9);
  for (double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) line += " " + FormatFixed(v, 9);
  return line + "\n";
}

ExportResult ExportTum(const ExportOptions& options) {
  const ExportSource source = ReadExportSource(options);
  const std::vector<FrameResult> estimates = ReadRunEstimates(options, source);
  const std::string header = "# t tx ty tz qx qy qz qw: tanker_from_receiver, time [s], translation [m]\n";
  std::string truth = header;
  std::set<size_t> selected;
  for (const FrameSidecar& frame : source.frames) {
    truth += TumLine(frame.time_s, frame.tanker_from_target);
    selected.insert(frame.index);
  }
  ExportResult result;
  result.frames = source.frames.size();
  WriteExportFile(options.out, "truth.tum", truth, result);
  if (options.run) {
    std::string text = header;
    size_t written = 0;
    for (const FrameResult& r : estimates) {
      if (!r.ok() || !selected.contains(r.frame)) continue;
      text += TumLine(r.time_s, r.estimate);
      ++written;
    }
    WriteExportFile(options.out, "estimate.tum", text, result);
    if (written < selected.size()) {
      result.notes.push_back("estimate.tum: " + std::to_string(selected.size() - written) +
                             " selected frames have no estimate in the run (not analyzed or not measured)");
    }
  }
  return result;
}

}  // namespace aar
