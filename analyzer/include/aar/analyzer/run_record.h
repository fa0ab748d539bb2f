#pragma once
// run.json, the record of an `aar-analyze run` (docs/analysis.md, "Output
// folder of run"): the frames it selected, and what the BOP scores and
// results file need (its options: options_record.h). RunAnalysis writes it; merge
// reads each shard's back and checks they agree.

#include <Eigen/Geometry>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "aar/analyzer/bop_metrics.h"
#include "aar/frame_selection.h"
#include "aar/rig.h"

namespace aar {

/// run.json's "frames": "begin:end", with " shard K/N" for a shard.
std::string DescribeSelection(const FrameSelection& selection);

/// run.json's "bop": the model's vertex count and diameter, the left
/// camera's image width and camera_from_tanker (bop_metrics.h).
nlohmann::json BopJson(const BopObject& object, const Camera& left);

/// The BOP scale and the camera pose a run.json's "bop" records.
BopScale BopScaleOf(const nlohmann::json& run);
Eigen::Isometry3d CameraFromTanker(const nlohmann::json& run);

/// A shard's run.json: present (the run finished) and with the keys merge
/// compares; throws aar::Error naming the file otherwise.
nlohmann::json ReadRunJson(const std::filesystem::path& dir);

}  // namespace aar
