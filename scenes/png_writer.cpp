#include "png_writer.h"

#include <zlib.h>

#include <array>
#include <cstdlib>
#include <string_view>

#include "aar/error.h"

namespace aar::scenes {
namespace {

void PutU32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(v >> shift));
}

void PutChunk(std::vector<std::uint8_t>& out, std::string_view type, const std::vector<std::uint8_t>& data) {
  PutU32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t type_at = out.size();
  out.insert(out.end(), type.begin(), type.end());
  out.insert(out.end(), data.begin(), data.end());
  const uLong crc = crc32(0L, out.data() + type_at, static_cast<uInt>(out.size() - type_at));
  PutU32(out, static_cast<std::uint32_t>(crc));
}

int Paeth(int a, int b, int c) {
  const int p = a + b - c;
  const int pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  if (pa <= pb && pa <= pc) return a;
  return pb <= pc ? b : c;
}

}  // namespace

std::vector<std::uint8_t> EncodePngRgb(int width, int height, const std::vector<std::uint8_t>& rgb) {
  const std::size_t stride = static_cast<std::size_t>(width) * 3;
  if (rgb.size() != stride * static_cast<std::size_t>(height)) {
    throw Error("EncodePngRgb: size mismatch");
  }
  // Filtered scanlines: for every row the filter with the smallest sum of
  // absolute (signed) residuals, the usual PNG heuristic.
  std::vector<std::uint8_t> filtered;
  filtered.reserve((stride + 1) * static_cast<std::size_t>(height));
  std::array<std::vector<std::uint8_t>, 5> candidates;
  for (auto& c : candidates) c.resize(stride);
  for (std::size_t y = 0; y < static_cast<std::size_t>(height); ++y) {
    const std::uint8_t* row = rgb.data() + y * stride;
    const std::uint8_t* up = y > 0 ? row - stride : nullptr;
    for (std::size_t i = 0; i < stride; ++i) {
      const int a = i >= 3 ? row[i - 3] : 0;
      const int b = up != nullptr ? up[i] : 0;
      const int c = (up != nullptr && i >= 3) ? up[i - 3] : 0;
      const int x = row[i];
      candidates[0][i] = static_cast<std::uint8_t>(x);
      candidates[1][i] = static_cast<std::uint8_t>(x - a);
      candidates[2][i] = static_cast<std::uint8_t>(x - b);
      candidates[3][i] = static_cast<std::uint8_t>(x - (a + b) / 2);
      candidates[4][i] = static_cast<std::uint8_t>(x - Paeth(a, b, c));
    }
    std::size_t best = 0;
    long best_cost = -1;
    for (std::size_t f = 0; f < candidates.size(); ++f) {
      long cost = 0;
      for (std::uint8_t r : candidates[f]) cost += std::abs(static_cast<int>(static_cast<std::int8_t>(r)));
      if (best_cost < 0 || cost < best_cost) {
        best_cost = cost;
        best = f;
      }
    }
    filtered.push_back(static_cast<std::uint8_t>(best));
    filtered.insert(filtered.end(), candidates[best].begin(), candidates[best].end());
  }

  uLongf compressed_size = compressBound(static_cast<uLong>(filtered.size()));
  std::vector<std::uint8_t> compressed(compressed_size);
  if (compress2(compressed.data(), &compressed_size, filtered.data(), static_cast<uLong>(filtered.size()),
                Z_BEST_COMPRESSION) != Z_OK) {
    throw Error("EncodePngRgb: zlib compression failed");
  }
  compressed.resize(compressed_size);

  std::vector<std::uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<std::uint8_t> header;
  PutU32(header, static_cast<std::uint32_t>(width));
  PutU32(header, static_cast<std::uint32_t>(height));
  header.insert(header.end(), {8, 2, 0, 0, 0});  // 8-bit, truecolour, deflate, adaptive filters, no interlace
  PutChunk(png, "IHDR", header);
  PutChunk(png, "IDAT", compressed);
  PutChunk(png, "IEND", {});
  return png;
}

}  // namespace aar::scenes
