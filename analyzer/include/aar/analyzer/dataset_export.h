#pragma once
// `aar-analyze export`: a dataset in the formats other tools read
// (docs/dataset-format.md, "Exports"). Each exporter is a file pair over
// export_source.h (export_bop, export_middlebury, export_tum, export_ros,
// export_rosbag) and one line in the table of dataset_export.cpp; nothing
// else names it.

#include <string>
#include <vector>

#include "aar/analyzer/export_source.h"

namespace aar {

struct Exporter {
  const char* format;       ///< the --format value
  const char* description;  ///< what it writes, for --help
  bool takes_run;           ///< also writes an `aar-analyze run` folder's estimates (--run)
  ExportResult (*run)(const ExportOptions& options);
};

/// Every exporter, in the order --help lists them.
const std::vector<Exporter>& Exporters();

/// The formats ("bop, middlebury, tum, ros or rosbag"), or those of the
/// exporters that take --run only.
std::string ExporterFormats(bool taking_run_only);

/// The exporter of `format`; throws aar::Error listing the formats otherwise.
const Exporter& FindExporter(const std::string& format);

/// Runs `exporter` into options.out, written as a whole (output_folder.h).
/// Everything that makes the export impossible (no manifest, a missing or
/// changed file, no depth truth where the format needs it, a --run the
/// format does not take) throws aar::Error naming the file before the first
/// file is written.
ExportResult ExportDataset(const Exporter& exporter, const ExportOptions& options);

}  // namespace aar
