#pragma once
// A dataset folder opened for reading (docs/dataset-format.md). Open reads
// manifest.json once and the render inputs it records once, each checked
// against its SHA-256 as it is read; sidecars and the files they list are
// read once each, checked the same way, when asked for. The analyzer's
// commands and layers take an OpenedDataset, never a folder path, so that a
// run reads each file of the dataset once and every check of a dataset's
// hashes is written here.

#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "aar/dataset.h"
#include "aar/flight_path.h"
#include "aar/rig.h"

namespace aar {

class OpenedDataset {
 public:
  /// Opens `folder`. Throws aar::Error naming the file and the reason when
  /// manifest.json is missing or malformed (ReadManifest); when a render
  /// input the manifest records (rig.json, flightpath.csv, receiver.glb,
  /// boom.glb, boom_tube.glb) differs from a recorded SHA-256, or is missing
  /// (flightpath.csv and receiver.glb may be: each frame's sidecar carries
  /// its truth, and an analysis may bring its own receiver model); when
  /// rig.json or flightpath.csv does not parse; or when the flight path's
  /// samples differ in number from frames.count.
  static OpenedDataset Open(const std::filesystem::path& folder);

  const std::filesystem::path& folder() const { return folder_; }
  const Manifest& manifest() const { return manifest_; }
  /// SHA-256 of manifest.json as read (run.json's dataset_manifest_sha256).
  const std::string& manifest_sha256() const { return manifest_sha256_; }
  /// folder/relative as text, for messages.
  std::string PathOf(const std::string& relative) const;

  /// rig.json's rig; throws aar::Error naming rig.json when the folder has none.
  const StereoRig& rig() const;
  bool has_rig() const { return rig_.has_value(); }
  /// flightpath.csv's samples; empty when the folder has no copy.
  const std::vector<FlightSample>& flight_path() const { return flight_path_; }
  /// The bytes of a render input (kReceiverModelName, kBoomModelName,
  /// kBoomTubeModelName), checked by Open; nullptr when the folder has none.
  const std::string* Input(const std::string& name) const;

  /// Sidecar `index` of `kind` ("frame" or "calib"), checked against
  /// manifest.json's SHA-256 (where listed) and against the render settings
  /// the manifest records (dataset.h, RenderSettings); throws aar::Error
  /// naming the sidecar when it is missing, changed, malformed, rendered with
  /// other settings, or holds another frame, and naming manifest.json when
  /// it is complete but does not list the sidecar.
  FrameSidecar Sidecar(const std::string& kind, size_t index) const;
  /// Throws aar::Error naming manifest.json when it is complete but does not
  /// list sidecar `index` of `kind` (which would then go unchecked).
  void CheckListed(const std::string& kind, size_t index) const;
  /// The file `ref` of a sidecar, checked against the sidecar's SHA-256 and,
  /// where manifest.json lists it, the manifest's; throws aar::Error naming
  /// the file when it is missing, unreadable or changed.
  std::string ReadFile(const FileRef& ref) const;
  /// The file at `relative` (e.g. kIdealCalibrationName), checked against
  /// manifest.json's SHA-256 where the manifest lists it; nullopt when the
  /// folder lacks it; throws aar::Error naming the file when it differs.
  std::optional<std::string> ReadIfPresent(const std::string& relative) const;

 private:
  std::filesystem::path folder_;
  Manifest manifest_;
  std::string manifest_sha256_;
  std::optional<StereoRig> rig_;
  std::vector<FlightSample> flight_path_;
  std::map<std::string, std::string> inputs_;  // receiver and boom models: name -> bytes
};

}  // namespace aar
