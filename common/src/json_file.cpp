#include "aar/json_file.h"

#include <algorithm>
#include <string>
#include <vector>

#include "aar/error.h"
#include "aar/file_io.h"

namespace aar {

nlohmann::json ReadJsonFile(const std::filesystem::path& path) {
  return ParseJsonText(ReadFileBytes(path), path.string());
}

nlohmann::json ParseJsonText(const std::string& text, const std::string& where) {
  // JSON leaves a repeated key's meaning open (the parser keeps the last); refused here.
  std::vector<std::vector<std::string>> keys;  // per open object: its keys so far
  const nlohmann::json::parser_callback_t no_repeated_keys = [&](int, nlohmann::json::parse_event_t event,
                                                                 nlohmann::json& parsed) {
    if (event == nlohmann::json::parse_event_t::object_start) {
      keys.emplace_back();
    } else if (event == nlohmann::json::parse_event_t::object_end && !keys.empty()) {
      keys.pop_back();
    } else if (event == nlohmann::json::parse_event_t::key && !keys.empty()) {
      const std::string key = parsed.get<std::string>();
      if (std::find(keys.back().begin(), keys.back().end(), key) != keys.back().end()) {
        throw Error(where + ": key \"" + key + "\" appears twice in one object");
      }
      keys.back().push_back(key);
    }
    return true;
  };
  try {
    return nlohmann::json::parse(text, no_repeated_keys);
  } catch (const nlohmann::json::exception& e) {
    throw Error(where + ": not valid JSON: " + e.what());
  }
}

void WriteJsonFile(const std::filesystem::path& path, const nlohmann::json& j) {
  WriteFileAtomic(path, j.dump(2) + "\n");
}

}  // namespace aar
