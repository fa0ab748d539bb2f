#pragma once
// A PNG's chunk structure checked before a decoder sees it. libpng reports a
// truncated or corrupt file on stderr itself before OpenCV returns an empty
// image; checked here first, such a file gets the project's one-line message.

#include <string>
#include <string_view>

namespace aar {

/// Throws aar::Error "<where>: not a whole PNG file (<reason>)" unless `bytes`
/// start with the PNG signature, continue as chunks whose lengths stay inside
/// the file and whose CRC-32 match (ISO/IEC 15948 5.3), begin with IHDR and
/// end with IEND.
void CheckPngStructure(std::string_view bytes, const std::string& where);

}  // namespace aar
