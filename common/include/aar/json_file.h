#pragma once
// Reading and writing the project's JSON files.

#include <filesystem>
#include <nlohmann/json.hpp>

namespace aar {

/// Reads a JSON file; throws aar::Error naming the file when it cannot be
/// read, is not valid JSON, or repeats a key within one object.
nlohmann::json ReadJsonFile(const std::filesystem::path& path);
/// Writes JSON (2-space indent, keys sorted, trailing newline) atomically.
void WriteJsonFile(const std::filesystem::path& path, const nlohmann::json& j);

}  // namespace aar
