#pragma once
// Reading and writing the project's JSON files.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

namespace aar {

/// Reads a JSON file; throws aar::Error naming the file when it cannot be
/// read, is not valid JSON, or repeats a key within one object.
nlohmann::json ReadJsonFile(const std::filesystem::path& path);
/// Parses JSON text read from `where` (a file's name), with ReadJsonFile's checks.
nlohmann::json ParseJsonText(const std::string& text, const std::string& where);
/// Writes JSON (2-space indent, keys sorted, trailing newline) atomically.
void WriteJsonFile(const std::filesystem::path& path, const nlohmann::json& j);

}  // namespace aar
