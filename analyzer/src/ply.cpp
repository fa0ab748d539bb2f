#include "aar/analyzer/ply.h"

#include <array>
#include <cstdint>
#include <cstring>
#include <sstream>

#include "aar/error.h"
#include "aar/file_io.h"

namespace aar {
namespace {

struct PlyProperty {
  std::string name;
  std::string type;
  int size = 0;       // bytes of a binary scalar
  bool list = false;  // list properties are only allowed in skipped ascii elements
};

struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> properties;
};

int PlyTypeSize(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" || type == "float32") {
    return 4;
  }
  if (type == "double" || type == "float64") return 8;
  return 0;
}

// One binary scalar as a double; `swap` reverses the bytes (file endianness
// differs from the machine's).
double PlyBinaryScalar(const unsigned char* p, const PlyProperty& property, bool swap) {
  unsigned char b[8];
  for (int i = 0; i < property.size; ++i) b[i] = swap ? p[property.size - 1 - i] : p[i];
  const std::string& t = property.type;
  if (t == "char" || t == "int8") return static_cast<double>(static_cast<int8_t>(b[0]));
  if (t == "uchar" || t == "uint8") return static_cast<double>(b[0]);
  if (t == "short" || t == "int16") {
    int16_t v;
    std::memcpy(&v, b, 2);
    return v;
  }
  if (t == "ushort" || t == "uint16") {
    uint16_t v;
    std::memcpy(&v, b, 2);
    return v;
  }
  if (t == "int" || t == "int32") {
    int32_t v;
    std::memcpy(&v, b, 4);
    return v;
  }
  if (t == "uint" || t == "uint32") {
    uint32_t v;
    std::memcpy(&v, b, 4);
    return v;
  }
  if (t == "float" || t == "float32") {
    float v;
    std::memcpy(&v, b, 4);
    return v;
  }
  double v;
  std::memcpy(&v, b, 8);
  return v;
}

bool MachineIsLittleEndian() {
  const uint16_t probe = 1;
  unsigned char first;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

// An "element NAME COUNT" header line, after its keyword.
PlyElement ParsePlyElementLine(std::istringstream& words, const std::string& at) {
  PlyElement element;
  long long count = -1;
  words >> element.name >> count;
  if (element.name.empty() || count < 0 || words.fail()) throw Error(at + ": malformed element line");
  element.count = static_cast<size_t>(count);
  return element;
}

// A "property TYPE NAME" or "property list COUNT_TYPE TYPE NAME" header
// line, after its keyword.
PlyProperty ParsePlyPropertyLine(std::istringstream& words, const std::string& at) {
  PlyProperty property;
  words >> property.type;
  if (property.type == "list") {
    std::string count_type;
    words >> count_type >> property.type;
    property.list = true;
  }
  words >> property.name;
  property.size = PlyTypeSize(property.type);
  if (property.name.empty() || property.size == 0) throw Error(at + ": malformed property line");
  return property;
}

struct PlyHeader {
  std::string format;
  std::vector<PlyElement> elements;
  size_t data_start = 0;  // the first byte after the "end_header" line
};

// Header: lines up to and including "end_header".
PlyHeader ParsePlyHeader(const std::string& bytes, const std::string& where) {
  PlyHeader header;
  size_t pos = 0;
  bool ended = false;
  for (int line_number = 1; pos < bytes.size(); ++line_number) {
    const size_t newline = bytes.find('\n', pos);
    if (newline == std::string::npos) break;
    std::string line = bytes.substr(pos, newline - pos);
    pos = newline + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    const std::string at = where + ": header line " + std::to_string(line_number);
    if (line_number == 1) {
      if (keyword != "ply") throw Error(where + ": not a PLY file (no 'ply' magic line)");
      continue;
    }
    if (keyword == "format") {
      std::string version;
      words >> header.format >> version;
      if (header.format != "ascii" && header.format != "binary_little_endian" && header.format != "binary_big_endian") {
        throw Error(at + ": unknown format '" + header.format + "'");
      }
    } else if (keyword == "element") {
      header.elements.push_back(ParsePlyElementLine(words, at));
    } else if (keyword == "property") {
      if (header.elements.empty()) throw Error(at + ": property before any element");
      header.elements.back().properties.push_back(ParsePlyPropertyLine(words, at));
    } else if (keyword == "end_header") {
      ended = true;
      break;
    } else if (keyword != "comment" && keyword != "obj_info" && !keyword.empty()) {
      throw Error(at + ": unknown keyword '" + keyword + "'");
    }
  }
  if (!ended) throw Error(where + ": PLY header has no end_header line");
  if (header.format.empty()) throw Error(where + ": PLY header has no format line");
  header.data_start = pos;
  return header;
}

struct PlyVertexLayout {
  size_t element = 0;                     // index of the vertex element in PlyHeader::elements
  std::array<int, 3> xyz = {-1, -1, -1};  // indices of the x, y and z properties in it
};

// The vertex element and its x, y, z properties.
PlyVertexLayout FindPlyVertexLayout(const std::vector<PlyElement>& elements, const std::string& where) {
  PlyVertexLayout layout;
  layout.element = elements.size();
  for (size_t e = 0; e < elements.size(); ++e) {
    if (elements[e].name == "vertex") {
      layout.element = e;
      break;
    }
  }
  if (layout.element == elements.size()) throw Error(where + ": PLY file has no vertex element");
  const PlyElement& vertex = elements[layout.element];
  std::array<int, 3>& xyz = layout.xyz;
  for (size_t p = 0; p < vertex.properties.size(); ++p) {
    for (int c = 0; c < 3; ++c) {
      if (vertex.properties[p].name == std::string(1, static_cast<char>('x' + c))) {
        xyz[static_cast<size_t>(c)] = static_cast<int>(p);
      }
    }
    if (vertex.properties[p].list) throw Error(where + ": list property in the vertex element is not supported");
  }
  if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0) throw Error(where + ": vertex element lacks x, y or z");
  return layout;
}

// Every item takes at least one byte (binary) or one line (ASCII): a count
// beyond the bytes left is a corrupt header, refused before any allocation.
void CheckPlyElementCounts(const std::vector<PlyElement>& elements, size_t data_bytes, const std::string& where) {
  for (const PlyElement& element : elements) {
    if (element.count > data_bytes) {
      throw Error(where + ": element '" + element.name + "' announces " + std::to_string(element.count) +
                  " items, more than the file's " + std::to_string(data_bytes) + " data bytes");
    }
  }
}

// The vertices of an ASCII file: one line per item, the vertex element's
// after those of the elements before it.
std::vector<Eigen::Vector3d> ReadAsciiPlyVertices(const std::string& bytes, const PlyHeader& header,
                                                  const PlyVertexLayout& layout, const std::string& where) {
  const std::vector<PlyElement>& elements = header.elements;
  const PlyElement& vertex = elements[layout.element];
  const std::array<int, 3>& xyz = layout.xyz;
  std::vector<Eigen::Vector3d> points;
  points.reserve(vertex.count);
  std::istringstream data(bytes.substr(header.data_start));
  std::string line;
  for (size_t e = 0; e < layout.element; ++e) {  // earlier elements: one line per item
    for (size_t i = 0; i < elements[e].count; ++i) {
      if (!std::getline(data, line)) throw Error(where + ": PLY data ends inside element '" + elements[e].name + "'");
    }
  }
  for (size_t i = 0; i < vertex.count; ++i) {
    if (!std::getline(data, line)) throw Error(where + ": PLY data ends after " + std::to_string(i) + " vertices");
    std::istringstream fields(line);
    std::vector<double> values(vertex.properties.size());
    for (double& v : values) {
      if (!(fields >> v)) throw Error(where + ": vertex " + std::to_string(i) + " has a malformed value");
    }
    points.emplace_back(values[static_cast<size_t>(xyz[0])], values[static_cast<size_t>(xyz[1])],
                        values[static_cast<size_t>(xyz[2])]);
  }
  return points;
}

// The position in a binary file's `bytes` after the first `count` elements,
// whose data starts at `pos`.
size_t SkipBinaryPlyElements(const std::string& bytes, size_t pos, const std::vector<PlyElement>& elements,
                             size_t count, const std::string& where) {
  for (size_t e = 0; e < count; ++e) {  // earlier elements: skip fixed-size items
    size_t item = 0;
    for (const PlyProperty& p : elements[e].properties) {
      if (p.list) throw Error(where + ": list property before the vertex element is not supported");
      item += static_cast<size_t>(p.size);
    }
    size_t skipped = 0;
    if (__builtin_mul_overflow(item, elements[e].count, &skipped) || skipped > bytes.size() - pos) {
      throw Error(where + ": PLY file is truncated inside element '" + elements[e].name + "'");
    }
    pos += skipped;
  }
  return pos;
}

// The vertices of a binary file (either endianness): fixed-size items, after
// those of the elements before the vertex element.
std::vector<Eigen::Vector3d> ReadBinaryPlyVertices(const std::string& bytes, const PlyHeader& header,
                                                   const PlyVertexLayout& layout, const std::string& where) {
  const PlyElement& vertex = header.elements[layout.element];
  const std::array<int, 3>& xyz = layout.xyz;
  std::vector<Eigen::Vector3d> points;
  points.reserve(vertex.count);
  const bool swap = (header.format == "binary_little_endian") != MachineIsLittleEndian();
  const size_t pos = SkipBinaryPlyElements(bytes, header.data_start, header.elements, layout.element, where);
  std::vector<size_t> offsets;
  size_t stride = 0;
  for (const PlyProperty& p : vertex.properties) {
    offsets.push_back(stride);
    stride += static_cast<size_t>(p.size);
  }
  if (pos > bytes.size() || (bytes.size() - pos) / stride < vertex.count) {
    throw Error(where + ": PLY file is truncated (" + std::to_string(vertex.count) + " vertices announced)");
  }
  const unsigned char* data = reinterpret_cast<const unsigned char*>(bytes.data()) + pos;
  for (size_t i = 0; i < vertex.count; ++i) {
    const unsigned char* item = data + i * stride;
    Eigen::Vector3d point;
    for (int c = 0; c < 3; ++c) {
      const size_t p = static_cast<size_t>(xyz[static_cast<size_t>(c)]);
      point[c] = PlyBinaryScalar(item + offsets[p], vertex.properties[p], swap);
    }
    points.push_back(point);
  }
  return points;
}

}  // namespace

void WritePly(const std::filesystem::path& path, const std::vector<Eigen::Vector3d>& points,
              const std::vector<std::string>& comments) {
  std::string bytes = "ply\nformat binary_little_endian 1.0\n";
  for (const std::string& comment : comments) {
    if (comment.find_first_of("\r\n") != std::string::npos) {
      throw Error(path.string() + ": PLY comments cannot hold line breaks");
    }
    bytes += "comment " + comment + "\n";
  }
  bytes += "element vertex " + std::to_string(points.size()) +
           "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  const size_t header_size = bytes.size();
  bytes.resize(header_size + points.size() * 12);
  unsigned char* out = reinterpret_cast<unsigned char*>(bytes.data()) + header_size;
  for (const Eigen::Vector3d& p : points) {
    for (int c = 0; c < 3; ++c) {
      const float value = static_cast<float>(p[c]);
      uint32_t bits;
      std::memcpy(&bits, &value, 4);
      for (int byte = 0; byte < 4; ++byte) *out++ = static_cast<unsigned char>(bits >> (8 * byte));
    }
  }
  WriteFileAtomic(path, bytes);
}

std::vector<Eigen::Vector3d> ReadPly(const std::filesystem::path& path) {
  const std::string where = path.string();
  const std::string bytes = ReadFileBytes(path);
  const PlyHeader header = ParsePlyHeader(bytes, where);
  const PlyVertexLayout layout = FindPlyVertexLayout(header.elements, where);
  CheckPlyElementCounts(header.elements, bytes.size() - header.data_start, where);
  std::vector<Eigen::Vector3d> points = header.format == "ascii" ? ReadAsciiPlyVertices(bytes, header, layout, where)
                                                                 : ReadBinaryPlyVertices(bytes, header, layout, where);
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) throw Error(where + ": vertex " + std::to_string(i) + " is not finite");
  }
  return points;
}

}  // namespace aar
