#pragma once
// run.json's "options" (docs/analysis.md, "Output folder of run"): every
// setting the analysis of the frames used, written by RunAnalysis, and read
// back to run the same analysis again (`aar-analyze run --options-from RUN`):
// a run is reproduced from its own record.

#include <nlohmann/json.hpp>
#include <string>

#include "aar/analyzer/analysis_run.h"

namespace aar {

/// run.json's "options": the preset, then every setting of the stages the
/// frames went through (a stage that was off: its section absent or false).
nlohmann::json OptionsJson(const AnalysisRunOptions& options);

/// Sets the analysis options of `options` (preset, frame options, reference
/// model, temporal filter, masks) to those `recorded` (a run.json's
/// "options") holds, leaving what the record does not decide (dataset,
/// output, frames, calibration, receiver model, progress, dumps) as it is.
/// OptionsJson of the result equals `recorded` for every record OptionsJson
/// writes. Throws aar::Error naming `where` and the first missing or
/// malformed key.
void ApplyRecordedOptions(const nlohmann::json& recorded, const std::string& where, AnalysisRunOptions& options);

}  // namespace aar
