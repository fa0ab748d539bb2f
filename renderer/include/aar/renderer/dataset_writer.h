#pragma once
// Writing the dataset folder (docs/dataset-format.md): the manifest, input
// copies and the final per-file hash list. Frames themselves are written by
// stereo_render_job.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace aar {

/// Renderer name, version and git hash, as recorded in manifests.
nlohmann::json RendererIdentity();

/// Creates DATASET/manifest.json from `header`, or, when one exists, checks
/// that every key of `header` that the existing manifest also has is equal
/// (same inputs, device, MSAA, image size) and merges the new sections in.
/// Throws aar::Error naming the first mismatching key otherwise. A different
/// renderer build only warns (the manifest keeps the first build's identity).
void OpenManifest(const std::filesystem::path& dataset, const nlohmann::json& header);

/// Copies `source` into the dataset as `name` (atomically) unless an identical
/// file is already there; returns the copy's SHA-256.
std::string CopyInput(const std::filesystem::path& dataset, const std::filesystem::path& source,
                      const std::string& name);

/// Recomputes the manifest's "files" list from the sidecars and the top-level
/// files, and sets "complete" when every frame and calibration pair the
/// manifest announces has a sidecar, then writes SHA256SUMS (every listed
/// file and manifest.json, for `sha256sum -c`). Returns "complete".
bool FinalizeManifest(const std::filesystem::path& dataset);

}  // namespace aar
