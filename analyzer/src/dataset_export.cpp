#include "aar/analyzer/dataset_export.h"

#include <algorithm>

#include "aar/analyzer/export_bop.h"
#include "aar/analyzer/export_middlebury.h"
#include "aar/analyzer/export_ros.h"
#include "aar/analyzer/export_rosbag.h"
#include "aar/analyzer/export_tum.h"
#include "aar/error.h"
#include "aar/output_folder.h"

namespace aar {

const std::vector<Exporter>& Exporters() {
  static const std::vector<Exporter> exporters = {
      {"bop", "6-DoF pose benchmark", false, ExportBop},
      {"middlebury", "stereo: calib.txt, disparity truth", false, ExportMiddlebury},
      {"tum", "trajectories", true, ExportTum},
      {"ros", "CameraInfo YAML", false, ExportRos},
      {"rosbag", "ROS 1 bag: images, CameraInfo, truth and estimates", true, ExportRosbag},
  };
  return exporters;
}

std::string ExporterFormats(bool taking_run_only) {
  std::vector<const char*> formats;
  for (const Exporter& e : Exporters()) {
    if (e.takes_run || !taking_run_only) formats.push_back(e.format);
  }
  std::string list;
  for (size_t i = 0; i < formats.size(); ++i) {
    list += std::string(i == 0 ? "" : i + 1 == formats.size() ? " or " : ", ") + formats[i];
  }
  return list;
}

const Exporter& FindExporter(const std::string& format) {
  for (const Exporter& e : Exporters()) {
    if (format == e.format) return e;
  }
  throw Error("--format '" + format + "': expected " + ExporterFormats(false));
}

ExportResult ExportDataset(const Exporter& exporter, const ExportOptions& options) {
  if (options.out.empty()) throw Error("export: no output folder given (--out)");
  CheckOutputFolder(options.out);
  if (options.run) {
    if (!exporter.takes_run) throw Error("--run: only with --format " + ExporterFormats(true));
    std::error_code ec;
    const std::filesystem::path run = std::filesystem::weakly_canonical(*options.run, ec);
    const std::filesystem::path out = std::filesystem::weakly_canonical(options.out, ec);
    if (std::mismatch(out.begin(), out.end(), run.begin(), run.end()).first == out.end()) {
      throw Error(options.out.string() + ": --out is the --run folder or holds it; export into another folder");
    }
  }
  ReadExportSource(options);  // the dataset and its frames, checked before anything is written
  // Written as a whole (output_folder.h): a failed or killed export leaves the previous output.
  StagedOutput staged(options.out, "export");
  ExportOptions into = options;
  into.out = staged.path();
  ExportResult result = exporter.run(into);
  staged.Commit();
  return result;
}

}  // namespace aar
