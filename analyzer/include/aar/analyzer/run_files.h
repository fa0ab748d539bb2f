#pragma once
// The files of an `aar-analyze run` folder (docs/analysis.md, "Output folder
// of run"), named once for the run that writes them and for the merge, the
// exports and the readers that read them.

namespace aar {

/// Result files of a run folder.
inline constexpr const char* kFramesCsvName = "frames.csv";
inline constexpr const char* kSummaryJsonName = "summary.json";
inline constexpr const char* kSummaryMarkdownName = "summary.md";
inline constexpr const char* kRunJsonName = "run.json";
inline constexpr const char* kBopResultsName = "bop_results.csv";
inline constexpr const char* kCalibrationYamlName = "calibration.yaml";
inline constexpr const char* kCalibrationReportName = "calibration_report.json";
inline constexpr const char* kFrameDumpDir = "frames";

}  // namespace aar
