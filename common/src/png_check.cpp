#include "aar/png_check.h"

#include <array>
#include <cstdint>

#include "aar/error.h"

namespace aar {
namespace {

// CRC-32 of ISO/IEC 15948 Annex D (polynomial 0xEDB88320, reflected).
uint32_t Crc32(std::string_view bytes) {
  static const std::array<uint32_t, 256> kTable = [] {
    std::array<uint32_t, 256> table{};
    for (uint32_t n = 0; n < 256; ++n) {
      uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      table[n] = c;
    }
    return table;
  }();
  uint32_t crc = 0xFFFFFFFFu;
  for (const char byte : bytes) crc = kTable[(crc ^ static_cast<unsigned char>(byte)) & 0xFF] ^ (crc >> 8);
  return crc ^ 0xFFFFFFFFu;
}

uint32_t BigEndian32(std::string_view bytes, size_t at) {
  uint32_t value = 0;
  for (size_t i = 0; i < 4; ++i) value = (value << 8) | static_cast<unsigned char>(bytes[at + i]);
  return value;
}

}  // namespace

void CheckPngStructure(std::string_view bytes, const std::string& where) {
  const auto fail = [&](const std::string& reason) { throw Error(where + ": not a whole PNG file (" + reason + ")"); };
  constexpr std::string_view kSignature("\x89PNG\r\n\x1a\n", 8);
  if (bytes.substr(0, kSignature.size()) != kSignature) fail("no PNG signature");
  size_t at = kSignature.size();
  bool first = true;
  while (true) {
    if (bytes.size() - at < 12) fail("truncated after " + std::to_string(at) + " bytes");
    const uint32_t length = BigEndian32(bytes, at);
    if (length > bytes.size() - at - 12) fail("truncated: a chunk runs past the end of the file");
    const std::string_view type_and_data = bytes.substr(at + 4, 4 + length);
    const std::string type(type_and_data.substr(0, 4));
    if (Crc32(type_and_data) != BigEndian32(bytes, at + 8 + length)) fail("chunk " + type + ": CRC error");
    if (first && type != "IHDR") fail("the first chunk is not IHDR");
    first = false;
    at += 12 + length;
    if (type == "IEND") break;
  }
  if (at != bytes.size()) fail(std::to_string(bytes.size() - at) + " bytes after IEND");
}

}  // namespace aar
