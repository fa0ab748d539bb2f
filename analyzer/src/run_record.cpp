#include "aar/analyzer/run_record.h"

#include <algorithm>

#include "aar/analyzer/run_files.h"
#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/json_file.h"

namespace aar {

std::string DescribeSelection(const FrameSelection& s) {
  std::string text =
      std::to_string(s.begin) + ":" + (s.end == static_cast<size_t>(-1) ? std::string() : std::to_string(s.end));
  if (s.shard_count > 1) text += " shard " + std::to_string(s.shard_index) + "/" + std::to_string(s.shard_count);
  return text;
}

nlohmann::json BopJson(const BopObject& object, const Camera& left) {
  const Eigen::Matrix4d camera_from_tanker = left.tanker_from_camera.inverse().matrix();
  nlohmann::json matrix = nlohmann::json::array();
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k) matrix.push_back(camera_from_tanker(i, k));
  return {{"object", "the receiver mesh's distinct vertices"},
          {"vertices", object.vertices().size()},
          {"diameter_m", object.diameter_m()},
          {"image_width_px", left.intrinsics.width_px},
          {"camera_from_tanker", matrix}};
}

BopScale BopScaleOf(const nlohmann::json& run) {
  const nlohmann::json& bop = run.at("bop");
  return {bop.at("diameter_m").get<double>(), bop.at("image_width_px").get<int>()};
}

Eigen::Isometry3d CameraFromTanker(const nlohmann::json& run) {
  const nlohmann::json& matrix = run.at("bop").at("camera_from_tanker");
  Eigen::Matrix4d m;
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k) m(i, k) = matrix.at(static_cast<size_t>(4 * i + k)).get<double>();
  return Eigen::Isometry3d(m);
}

nlohmann::json ReadRunJson(const std::filesystem::path& dir) {
  const std::filesystem::path path = dir / kRunJsonName;
  if (!std::filesystem::is_regular_file(path)) {
    throw Error(path.string() + ": missing (the run did not finish, or this is not a run folder)");
  }
  nlohmann::json run = ReadJsonFile(path);
  for (const char* key :
       {"schema", "dataset_manifest_sha256", "model", "calibration", "options", "frames_analyzed", "bop"}) {
    if (!run.is_object() || !run.contains(key)) throw Error(path.string() + ": incomplete run.json (no '" + key + "')");
  }
  if (run.at("schema") != "aar-run/1") throw Error(path.string() + ": schema is not aar-run/1");
  if (!run.at("model").is_string() || !run.at("dataset_manifest_sha256").is_string() ||
      !run.at("frames_analyzed").is_number_unsigned()) {
    throw Error(path.string() + ": malformed run.json (model, dataset_manifest_sha256 or frames_analyzed)");
  }
  const nlohmann::json& bop = run.at("bop");
  const bool bop_ok = bop.is_object() && bop.contains("diameter_m") && bop.at("diameter_m").is_number() &&
                      bop.at("diameter_m").get<double>() > 0.0 && bop.contains("image_width_px") &&
                      bop.at("image_width_px").is_number_unsigned() && bop.at("image_width_px").get<int>() > 0 &&
                      bop.contains("camera_from_tanker") && bop.at("camera_from_tanker").is_array() &&
                      bop.at("camera_from_tanker").size() == 16 &&
                      std::all_of(bop.at("camera_from_tanker").begin(), bop.at("camera_from_tanker").end(),
                                  [](const nlohmann::json& v) { return v.is_number(); });
  if (!bop_ok) {
    throw Error(path.string() +
                ": malformed run.json ('bop' needs diameter_m > 0, image_width_px > 0 and a 16-number "
                "camera_from_tanker)");
  }
  return run;
}

}  // namespace aar
