#include "aar/text.h"

#include <charconv>
#include <cmath>

#include "aar/error.h"

namespace aar {

std::string TrimCr(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return std::string(line);
}

std::vector<std::string> SplitCsvLine(std::string_view line) {
  std::vector<std::string> fields;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    fields.emplace_back(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return fields;
}

double ParseFiniteDouble(std::string_view text, const std::string& where) {
  std::string_view t = text;
  while (!t.empty() && t.front() == ' ') t.remove_prefix(1);
  while (!t.empty() && t.back() == ' ') t.remove_suffix(1);
  double value = 0.0;
  const char* begin = t.data();
  const char* end = t.data() + t.size();
  if (!t.empty() && *begin == '+') ++begin;
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  if (t.empty() || ec != std::errc() || ptr != end || !std::isfinite(value)) {
    throw Error(where + ": '" + std::string(text) + "' is not a finite number");
  }
  return value;
}

long long ParseInteger(std::string_view text, const std::string& where) {
  long long value = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || ptr != text.data() + text.size() || value < 0) {
    throw Error(where + ": '" + std::string(text) + "' is not a non-negative integer");
  }
  return value;
}

std::string PrintableText(std::string_view text) {
  static const char* kHex = "0123456789ABCDEF";
  std::string out;
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7f) {
      out += c;
    } else {
      out += "\\x";
      out += kHex[byte >> 4];
      out += kHex[byte & 15];
    }
  }
  return out;
}

std::string FormatFixed(double value, int decimals) {
  char buffer[64];
  // Beyond 10^15 a double has no fixed-point digits to show: its shortest form ("1e+300") instead.
  const auto [ptr, ec] = std::abs(value) < 1e15 || !std::isfinite(value)
                             ? std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::fixed, decimals)
                             : std::to_chars(buffer, buffer + sizeof(buffer), value);
  std::string s(buffer, ec == std::errc() ? ptr : buffer);
  if (s.starts_with('-') && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);
  return s;
}

}  // namespace aar
