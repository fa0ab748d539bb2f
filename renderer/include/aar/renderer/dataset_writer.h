#pragma once
// Writing the dataset folder (docs/dataset-format.md): the manifest, input
// copies and the final per-file hash list. Frames themselves are written by
// stereo_render_job.

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "aar/folder_lock.h"

namespace aar {

/// Renderer name, version and git hash, as recorded in manifests.
nlohmann::json RendererIdentity();

/// The manifest a run of `kind` ("frame" or "calib") with `header` writes:
/// `header` itself for a new dataset, or the existing manifest with
/// `header`'s sections merged in, after checking that the render settings of
/// that kind (dataset.h, RenderSettings) are equal both ways: a setting in
/// one and not the other differs. Throws aar::Error naming the first
/// difference, or when frames/ or calib/ hold files but there is no manifest.
/// A different renderer build only warns (the manifest keeps the first
/// build's identity). Writes nothing.
nlohmann::json MergeManifest(const std::filesystem::path& dataset, const std::string& kind,
                             const nlohmann::json& header);

/// Under the dataset's manifest lock (folder_lock.h): MergeManifest, then
/// `write_inputs` (the copies of the inputs), then the manifest; so a refused
/// run writes nothing and two runs never both pass the check. Returns the
/// settings hash every sidecar of this kind records.
std::string OpenManifest(const std::filesystem::path& dataset, const std::string& kind, const nlohmann::json& header,
                         const std::function<void()>& write_inputs);

/// Copies `source` into the dataset as `name` (atomically) unless an identical
/// file is already there; throws when its SHA-256 is no longer `sha256`.
void CopyInput(const std::filesystem::path& dataset, const std::filesystem::path& source, const std::string& name,
               const std::string& sha256);

/// The lock every writing run holds for its whole duration (shared, so that
/// shards render into one folder together). The first writer, finding no
/// other, removes the `.tmp*` files interrupted writes left (folder_lock.h).
FileLock LockDatasetForWriting(const std::filesystem::path& dataset);

/// Recomputes the manifest's "files" list from the sidecars and the top-level
/// files (throws aar::Error naming a sidecar whose settings hash is not the
/// manifest's: frames of mixed settings), and sets "complete" when every frame and calibration pair the
/// manifest announces has a sidecar, then writes SHA256SUMS (every listed
/// file and manifest.json, for `sha256sum -c`). Returns "complete". Holds
/// the manifest lock while it reads and writes.
bool FinalizeManifest(const std::filesystem::path& dataset);

}  // namespace aar
