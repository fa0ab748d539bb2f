#pragma once
// Integers read from JSON files with their range checked: nlohmann's get<int>()
// converts a float such as 1e300 with a static_cast, which is undefined
// behaviour (found by tests/fuzz), and wraps negative values into size_t.

#include <nlohmann/json.hpp>
#include <string>

#include "aar/error.h"

namespace aar {

/// `j` as an integer in [min, max]; throws aar::Error "<where>: ..." when it is
/// not an integer number (1.0 and 1e3 are not) or out of range.
inline long long JsonInteger(const nlohmann::json& j, long long min, long long max, const std::string& where) {
  if (j.is_number_unsigned()) {
    if (j.get<unsigned long long>() > static_cast<unsigned long long>(max)) {
      throw Error(where + " " + j.dump() + " is above " + std::to_string(max));
    }
  } else if (!j.is_number_integer()) {
    throw Error(where + " must be an integer, not " + j.dump());
  }
  const long long value = j.get<long long>();
  if (value < min || value > max) {
    throw Error(where + " " + std::to_string(value) + " is outside [" + std::to_string(min) + ", " +
                std::to_string(max) + "]");
  }
  return value;
}

}  // namespace aar
