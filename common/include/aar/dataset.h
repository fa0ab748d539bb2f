#pragma once
// The dataset folder schema (docs/dataset-format.md, schema "aar-dataset/1"):
//
//   DATASET/manifest.json            what made the dataset, and SHA-256 of every file
//   DATASET/SHA256SUMS               the same hashes and the manifest's, for `sha256sum -c`
//   DATASET/rig.json                 the rig used (scenes/rig.json format)
//   DATASET/flightpath.csv           the flight path used
//   DATASET/receiver.glb             the receiver model used
//   DATASET/boom.glb, boom_tube.glb  with the boom: its models (boom.h)
//   DATASET/calibration_ideal.yaml   the exact calibration (OpenCV FileStorage)
//   DATASET/frames/NNNNNN.json       per-frame truth sidecar
//   DATASET/frames/NNNNNN_left.png   8-bit sRGB, MSAA-resolved
//   DATASET/frames/NNNNNN_right.png
//   DATASET/frames/NNNNNN_left_depth.exr   (with --depth) float32 metres along the optical axis
//   DATASET/frames/NNNNNN_left_mask.png, NNNNNN_left_silhouette.png   (with --depth) object ids, receiver alone
//   DATASET/frames/NNNNNN_right_*        (with --depth-right) the same for the right camera
//   DATASET/calib/NNNNNN.json, NNNNNN_left.png, NNNNNN_right.png   calibration-board pairs

#include <cstddef>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "aar/boom.h"
#include "aar/json_file.h"
#include "aar/pose.h"
#include "aar/rig.h"

namespace aar {

inline constexpr const char* kDatasetSchema = "aar-dataset/1";
inline constexpr const char* kFrameSchema = "aar-frame/1";
inline constexpr const char* kManifestName = "manifest.json";
inline constexpr const char* kChecksumsName = "SHA256SUMS";
inline constexpr const char* kRigName = "rig.json";
inline constexpr const char* kFlightPathName = "flightpath.csv";
inline constexpr const char* kReceiverModelName = "receiver.glb";
inline constexpr const char* kBoomModelName = "boom.glb";           ///< with the boom: its fixed part
inline constexpr const char* kBoomTubeModelName = "boom_tube.glb";  ///< with the boom: its telescoping tube
/// Object id of the boom in the masks (docs/dataset-format.md, "Images").
inline constexpr int kBoomMaskId = 6;
/// Object id of the receiver's lights in the masks (with --receiver-lights).
inline constexpr int kReceiverLightsMaskId = 7;
inline constexpr const char* kIdealCalibrationName = "calibration_ideal.yaml";
inline constexpr const char* kFramesDir = "frames";
inline constexpr const char* kCalibDir = "calib";
/// Most frames (or calibration pairs) a manifest may announce: 10^7 is about
/// 46 hours at 60 Hz; larger counts are refused as corrupt.
inline constexpr size_t kMaxDatasetFrames = 10'000'000;

/// Calibration board geometry (thesis 3.3).
struct BoardSpec {
  int inner_corners_x = 16;  ///< inner corners along a row (board x axis)
  int inner_corners_y = 17;  ///< inner corners along a column (board y axis)
  double square_m = 0.5;     ///< square size [m]
};

/// A file of the dataset, path relative to the dataset root.
struct FileRef {
  std::string path;
  std::string sha256;
};

/// Per-frame truth sidecar. `kind` is "frame" (flight-path sample; the
/// target is the receiver) or "calib" (calibration pair; the target is the board).
struct FrameSidecar {
  std::string kind = "frame";
  size_t index = 0;
  double time_s = 0.0;             ///< flight-path time (frames only)
  Pose tanker_from_target;         ///< tanker_from_receiver or tanker_from_board
  double range_m = 0.0;            ///< left camera centre to target origin [m]
  std::string region = "none";     ///< A, B, C or none (frames only)
  double in_view_left = 0.0;       ///< fraction of target model vertices inside the left image
  double in_view_right = 0.0;      ///< same for the right image
  StereoRig rig;                   ///< ideal intrinsics and extrinsics
  std::optional<BoardSpec> board;  ///< calib only
  /// Frames with the boom in the scene: the boom operator's controls
  /// (written as `boom`, with `tanker_from_boom` and `tanker_from_boom_tube`
  /// derived from them by boom.h); absent otherwise.
  std::optional<BoomPose> boom;
  /// SHA-256 of the render settings that made this pair (RenderSettings of
  /// its kind, compact JSON); empty in datasets made before it was recorded.
  std::string settings_sha256;
  /// "left", "right"; with depth truth "left_depth", "left_mask", "left_silhouette" (and "right_...")
  std::map<std::string, FileRef> files;
};

/// Zero-padded frame stem, e.g. 12 -> "000012".
std::string FrameStem(size_t index);
/// Sidecar path of frame `index` of `kind` inside `dataset`.
std::filesystem::path SidecarPath(const std::filesystem::path& dataset, const std::string& kind, size_t index);

nlohmann::json PoseToJson(const Pose& pose);
Pose PoseFromJson(const nlohmann::json& j, const std::string& where);
nlohmann::json SidecarToJson(const FrameSidecar& sidecar);
/// Reads a sidecar; throws aar::Error naming the file and the reason.
FrameSidecar ReadSidecar(const std::filesystem::path& path);
/// The same for a sidecar's JSON, read from `where`.
FrameSidecar ParseSidecar(const nlohmann::json& j, const std::string& where);
/// True when the sidecar exists, parses, records `settings_sha256` (or no
/// settings hash, in datasets made before it was recorded), and every file it
/// lists exists with the recorded SHA-256 (the resume check).
bool SidecarVerified(const std::filesystem::path& dataset, const std::filesystem::path& sidecar_path,
                     const std::string& settings_sha256);

/// The parts of manifest.json that readers need; `json` holds all of it.
struct Manifest {
  std::string schema;
  size_t frame_count = 0;                    ///< flight-path frames (0 when none were rendered)
  size_t calib_pair_count = 0;               ///< calibration pairs (0 when none were rendered)
  bool complete = false;                     ///< every frame and pair present and hashed in `files`
  std::map<std::string, std::string> files;  ///< relative path -> SHA-256
  std::string frame_settings_sha256;         ///< RenderSettingsSha256(json, "frame"); empty without frames
  std::string calib_settings_sha256;         ///< RenderSettingsSha256(json, "calib"); empty without calib
  nlohmann::json json;
};

/// The manifest keys that shape the pairs of one kind ("frame" or "calib"):
/// schema, device, image, the kind's own inputs and its section (`frames` or
/// `calib`). A resume compares them both ways, and every sidecar records
/// their hash (docs/dataset-format.md, "Resume").
nlohmann::json RenderSettings(const nlohmann::json& manifest, const std::string& kind);
/// SHA-256 of RenderSettings' compact JSON (keys sorted); empty when the
/// manifest has no section of that kind.
std::string RenderSettingsSha256(const nlohmann::json& manifest, const std::string& kind);

/// True for 64 lower-case hex digits.
bool IsSha256Hex(const std::string& text);

/// Reads DATASET/manifest.json; throws aar::Error when missing or malformed
/// (counts above kMaxDatasetFrames, `files` not an object of SHA-256 values,
/// or `complete` with an empty `files`). A dataset is read for analysis
/// through OpenedDataset (opened_dataset.h).
Manifest ReadManifest(const std::filesystem::path& dataset);
/// The same checks on a manifest's JSON, read from `where`.
Manifest ParseManifest(nlohmann::json json, const std::string& where);

}  // namespace aar
