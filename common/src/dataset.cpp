#include "aar/dataset.h"

#include <cstdio>
#include <vector>

#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/json_number.h"

namespace aar {

std::string FrameStem(size_t index) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%06zu", index);
  return buffer;
}

std::filesystem::path SidecarPath(const std::filesystem::path& dataset, const std::string& kind, size_t index) {
  return dataset / (kind == "calib" ? kCalibDir : kFramesDir) / (FrameStem(index) + ".json");
}

nlohmann::json PoseToJson(const Pose& pose) {
  nlohmann::json j = IsometryToJson(IsometryFromPose(pose));
  j["roll_deg"] = pose.roll_deg;
  j["pitch_deg"] = pose.pitch_deg;
  j["yaw_deg"] = pose.yaw_deg;
  return j;
}

Pose PoseFromJson(const nlohmann::json& j, const std::string& where) {
  try {
    Pose pose;
    for (int i = 0; i < 3; ++i) pose.translation_m(i) = j.at("translation_m").at(i).get<double>();
    pose.roll_deg = j.at("roll_deg").get<double>();
    pose.pitch_deg = j.at("pitch_deg").get<double>();
    pose.yaw_deg = j.at("yaw_deg").get<double>();
    return pose;
  } catch (const nlohmann::json::exception& e) {
    throw Error(where + ": bad pose: " + e.what());
  }
}

nlohmann::json SidecarToJson(const FrameSidecar& s) {
  nlohmann::json j;
  j["schema"] = kFrameSchema;
  j["kind"] = s.kind;
  j["index"] = s.index;
  const bool calib = s.kind == "calib";
  j[calib ? "tanker_from_board" : "tanker_from_receiver"] = PoseToJson(s.tanker_from_target);
  if (!calib) {
    j["time_s"] = s.time_s;
    j["region"] = s.region;
  }
  j["range_m"] = s.range_m;
  j["in_view"] = {{"left", s.in_view_left}, {"right", s.in_view_right}};
  j["rig"] = RigToJson(s.rig);
  j["right_from_left"] = IsometryToJson(s.rig.RightFromLeft());
  // cam_from_target = inverse(tanker_from_cam) * tanker_from_target, per camera (OpenCV camera frame).
  const Eigen::Isometry3d tanker_from_target = IsometryFromPose(s.tanker_from_target);
  j[calib ? "cam_from_board" : "cam_from_receiver"] = {
      {"left", IsometryToJson(s.rig.left.tanker_from_camera.inverse() * tanker_from_target)},
      {"right", IsometryToJson(s.rig.right.tanker_from_camera.inverse() * tanker_from_target)}};
  if (s.board) {
    j["board"] = {{"inner_corners", {s.board->inner_corners_x, s.board->inner_corners_y}},
                  {"square_m", s.board->square_m}};
  }
  if (s.boom) {
    j["boom"] = {{"pitch_deg", s.boom->pitch_deg},
                 {"roll_deg", s.boom->roll_deg},
                 {"extension_m", s.boom->extension_m},
                 {"tanker_from_boom", IsometryToJson(TankerFromBoom(*s.boom))},
                 {"tanker_from_boom_tube", IsometryToJson(TankerFromBoomTube(*s.boom))}};
  }
  if (!s.settings_sha256.empty()) j["settings_sha256"] = s.settings_sha256;
  nlohmann::json files = nlohmann::json::object();
  for (const auto& [name, ref] : s.files) files[name] = {{"path", ref.path}, {"sha256", ref.sha256}};
  j["files"] = files;
  return j;
}

FrameSidecar ReadSidecar(const std::filesystem::path& path) { return ParseSidecar(ReadJsonFile(path), path.string()); }

FrameSidecar ParseSidecar(const nlohmann::json& j, const std::string& where) {
  try {
    if (j.value("schema", "") != kFrameSchema) throw Error(where + ": schema is not " + kFrameSchema);
    FrameSidecar s;
    s.kind = j.at("kind").get<std::string>();
    if (s.kind != "frame" && s.kind != "calib") throw Error(where + ": unknown kind '" + s.kind + "'");
    s.index = static_cast<size_t>(JsonInteger(j.at("index"), 0, kMaxDatasetFrames, where + ": index"));
    const bool calib = s.kind == "calib";
    s.tanker_from_target = PoseFromJson(j.at(calib ? "tanker_from_board" : "tanker_from_receiver"), where);
    if (!calib) {
      s.time_s = j.at("time_s").get<double>();
      s.region = j.at("region").get<std::string>();
    }
    s.range_m = j.at("range_m").get<double>();
    s.in_view_left = j.at("in_view").at("left").get<double>();
    s.in_view_right = j.at("in_view").at("right").get<double>();
    s.rig = RigFromJson(j.at("rig"), where);
    if (j.contains("board")) {
      BoardSpec b;
      b.inner_corners_x = static_cast<int>(
          JsonInteger(j.at("board").at("inner_corners").at(0), 2, 1000, where + ": board.inner_corners[0]"));
      b.inner_corners_y = static_cast<int>(
          JsonInteger(j.at("board").at("inner_corners").at(1), 2, 1000, where + ": board.inner_corners[1]"));
      b.square_m = j.at("board").at("square_m").get<double>();
      if (!(b.square_m > 0.0)) throw Error(where + ": board.square_m must be positive");
      s.board = b;
    }
    if (j.contains("boom")) {
      const nlohmann::json& b = j.at("boom");
      s.boom =
          BoomPose{b.at("pitch_deg").get<double>(), b.at("roll_deg").get<double>(), b.at("extension_m").get<double>()};
      s.boom->Check(where + ": boom");
    }
    if (j.contains("settings_sha256")) {
      s.settings_sha256 = j.at("settings_sha256").get<std::string>();
      if (!IsSha256Hex(s.settings_sha256)) throw Error(where + ": settings_sha256 is not a SHA-256");
    }
    for (const auto& [name, ref] : j.at("files").items()) {
      s.files[name] = FileRef{ref.at("path").get<std::string>(), ref.at("sha256").get<std::string>()};
    }
    if (!s.files.contains("left") || !s.files.contains("right")) throw Error(where + ": files.left/right missing");
    return s;
  } catch (const nlohmann::json::exception& e) {
    throw Error(where + ": malformed sidecar: " + e.what());
  }
}

bool SidecarVerified(const std::filesystem::path& dataset, const std::filesystem::path& sidecar_path,
                     const std::string& settings_sha256) {
  if (!std::filesystem::is_regular_file(sidecar_path)) return false;
  try {
    const FrameSidecar s = ReadSidecar(sidecar_path);
    if (!s.settings_sha256.empty() && s.settings_sha256 != settings_sha256) return false;
    for (const auto& [name, ref] : s.files) {
      const std::filesystem::path file = dataset / ref.path;
      if (!std::filesystem::is_regular_file(file) || Sha256File(file) != ref.sha256) return false;
    }
    return true;
  } catch (const Error&) {
    return false;
  }
}

nlohmann::json RenderSettings(const nlohmann::json& manifest, const std::string& kind) {
  // The inputs each kind reads; the other kind's inputs do not shape its pairs.
  static const std::vector<std::string> kFrameInputs = {
      "rig", "receiver_model", "tanker_model", "flight_path", "boom_model", "boom_tube_model", "propeller_model"};
  static const std::vector<std::string> kCalibInputs = {"rig", "board_model"};
  const bool calib = kind == "calib";
  nlohmann::json settings = nlohmann::json::object();
  for (const char* key : {"schema", "device", "image", calib ? "calib" : "frames"}) {
    if (manifest.is_object() && manifest.contains(key)) settings[key] = manifest.at(key);
  }
  nlohmann::json inputs = nlohmann::json::object();
  if (manifest.is_object() && manifest.contains("inputs") && manifest.at("inputs").is_object()) {
    for (const std::string& key : calib ? kCalibInputs : kFrameInputs) {
      if (manifest.at("inputs").contains(key)) inputs[key] = manifest.at("inputs").at(key);
    }
  }
  settings["inputs"] = inputs;
  return settings;
}

std::string RenderSettingsSha256(const nlohmann::json& manifest, const std::string& kind) {
  if (!manifest.is_object() || !manifest.contains(kind == "calib" ? "calib" : "frames")) return "";
  return Sha256Hex(RenderSettings(manifest, kind).dump());
}

bool IsSha256Hex(const std::string& text) {
  return text.size() == 64 && text.find_first_not_of("0123456789abcdef") == std::string::npos;
}

Manifest ReadManifest(const std::filesystem::path& dataset) {
  const std::filesystem::path path = dataset / kManifestName;
  if (!std::filesystem::is_regular_file(path)) {
    throw Error(path.string() + ": no manifest (is '" + dataset.string() + "' a dataset folder?)");
  }
  return ParseManifest(ReadJsonFile(path), path.string());
}

Manifest ParseManifest(nlohmann::json json, const std::string& where) {
  Manifest m;
  m.json = std::move(json);
  try {
    m.schema = m.json.at("schema").get<std::string>();
    if (m.schema != kDatasetSchema) throw Error(where + ": unsupported schema '" + m.schema + "'");
    // Counts above kMaxDatasetFrames are corrupt: a run would allocate for every frame.
    for (const auto& [section, count] : {std::pair{"frames", &m.frame_count}, {"calib", &m.calib_pair_count}}) {
      if (!m.json.contains(section)) continue;
      *count = static_cast<size_t>(
          JsonInteger(m.json.at(section).at("count"), 0, kMaxDatasetFrames, where + ": " + section + ".count"));
    }
    m.complete = m.json.value("complete", false);
    const nlohmann::json& files = m.json.at("files");
    if (!files.is_object()) throw Error(where + ": 'files' must map relative paths to SHA-256");
    for (const auto& [name, hash] : files.items()) {
      m.files[name] = hash.get<std::string>();
      if (!IsSha256Hex(m.files[name])) throw Error(where + ": files['" + name + "'] is not a SHA-256");
    }
    if (m.complete && m.files.empty()) throw Error(where + ": complete, but 'files' lists nothing");
    m.frame_settings_sha256 = RenderSettingsSha256(m.json, "frame");
    m.calib_settings_sha256 = RenderSettingsSha256(m.json, "calib");
  } catch (const nlohmann::json::exception& e) {
    throw Error(where + ": malformed manifest: " + e.what());
  }
  return m;
}

}  // namespace aar
