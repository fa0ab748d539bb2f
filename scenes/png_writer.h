// Minimal deterministic PNG encoder (8-bit RGB, zlib level 9, per-row
// adaptive filter choice), so the generator needs no image library.
#pragma once

#include <cstdint>
#include <vector>

namespace aar::scenes {

/// Encodes `rgb` (width * height * 3 bytes, rows top to bottom) as a PNG file image.
std::vector<std::uint8_t> EncodePngRgb(int width, int height, const std::vector<std::uint8_t>& rgb);

}  // namespace aar::scenes
