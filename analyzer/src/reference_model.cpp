#include "aar/analyzer/reference_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>

#include "aar/error.h"
#include "aar/file_io.h"

namespace aar {
namespace {

// A real in [0, 1) from the top 53 bits of one raw mt19937_64 draw; the raw
// sequence is fixed by the C++ standard, so samples match on every platform.
double Uniform01(std::mt19937_64& generator) { return static_cast<double>(generator() >> 11) * 0x1.0p-53; }

// Depth along the optical axis of the nearest surface at each pixel centre.
struct DepthBuffer {
  int width = 0;
  int height = 0;
  std::vector<float> depth_m;  // row-major, +inf where no surface
  float At(int x, int y) const { return depth_m[static_cast<size_t>(y) * static_cast<size_t>(width) + x]; }
};

// Intrinsics of a raster of width x height covering the same field of view
// (pixel centres at integers, so the image edge -0.5 maps to -0.5).
Intrinsics ScaledIntrinsics(const Intrinsics& k, int width, int height) {
  Intrinsics s = k;
  const double sx = static_cast<double>(width) / k.width_px;
  const double sy = static_cast<double>(height) / k.height_px;
  s.width_px = width;
  s.height_px = height;
  s.fx_px = k.fx_px * sx;
  s.fy_px = k.fy_px * sy;
  s.cx_px = (k.cx_px + 0.5) * sx - 0.5;
  s.cy_px = (k.cy_px + 0.5) * sy - 0.5;
  return s;
}

// Sutherland-Hodgman clip of a triangle against the half space z >= near.
int ClipNear(const std::array<Eigen::Vector3d, 3>& in, double near_m, std::array<Eigen::Vector3d, 4>& out) {
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d& a = in[static_cast<size_t>(i)];
    const Eigen::Vector3d& b = in[static_cast<size_t>((i + 1) % 3)];
    const bool a_in = a.z() >= near_m;
    const bool b_in = b.z() >= near_m;
    if (a_in) out[static_cast<size_t>(n++)] = a;
    if (a_in != b_in) out[static_cast<size_t>(n++)] = a + (b - a) * ((near_m - a.z()) / (b.z() - a.z()));
  }
  return n;
}

// Scan-converts one triangle (camera frame, all z >= near) into the buffer.
void RasterizeTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                       const Intrinsics& k, DepthBuffer& buffer) {
  const std::array<Eigen::Vector3d, 3> cam = {a, b, c};
  std::array<Eigen::Vector2d, 3> px;
  std::array<double, 3> inverse_z;
  for (size_t i = 0; i < 3; ++i) {
    inverse_z[i] = 1.0 / cam[i].z();
    px[i] =
        Eigen::Vector2d(k.fx_px * cam[i].x() * inverse_z[i] + k.cx_px, k.fy_px * cam[i].y() * inverse_z[i] + k.cy_px);
  }
  const auto edge = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, double x, double y) {
    return (q.x() - p.x()) * (y - p.y()) - (q.y() - p.y()) * (x - p.x());
  };
  const double area = edge(px[0], px[1], px[2].x(), px[2].y());
  if (!(std::abs(area) > 1e-12)) return;  // degenerate or edge-on
  const double min_u = std::min({px[0].x(), px[1].x(), px[2].x()});
  const double max_u = std::max({px[0].x(), px[1].x(), px[2].x()});
  const double min_v = std::min({px[0].y(), px[1].y(), px[2].y()});
  const double max_v = std::max({px[0].y(), px[1].y(), px[2].y()});
  const int x0 = static_cast<int>(std::max(0.0, std::ceil(min_u)));
  const int x1 = static_cast<int>(std::min(buffer.width - 1.0, std::floor(max_u)));
  const int y0 = static_cast<int>(std::max(0.0, std::ceil(min_v)));
  const int y1 = static_cast<int>(std::min(buffer.height - 1.0, std::floor(max_v)));
  const double inverse_area = 1.0 / area;
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      // Barycentric weights of the pixel centre; closed edges (>= 0) so that
      // shared edges have no cracks (a pixel written twice keeps the minimum).
      const double w0 = edge(px[1], px[2], x, y) * inverse_area;
      const double w1 = edge(px[2], px[0], x, y) * inverse_area;
      const double w2 = edge(px[0], px[1], x, y) * inverse_area;
      if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
      // Perspective-correct depth: 1/z is affine in image coordinates.
      const double z = 1.0 / (w0 * inverse_z[0] + w1 * inverse_z[1] + w2 * inverse_z[2]);
      float& stored = buffer.depth_m[static_cast<size_t>(y) * static_cast<size_t>(buffer.width) + x];
      stored = std::min(stored, static_cast<float>(z));
    }
  }
}

DepthBuffer RasterizeDepth(const TriangleMesh& mesh, const Intrinsics& k, const Eigen::Isometry3d& cam_from_receiver,
                           double near_m) {
  DepthBuffer buffer;
  buffer.width = k.width_px;
  buffer.height = k.height_px;
  buffer.depth_m.assign(static_cast<size_t>(k.width_px) * static_cast<size_t>(k.height_px),
                        std::numeric_limits<float>::infinity());
  std::vector<Eigen::Vector3d> vertices_in_cam(mesh.vertices.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i) vertices_in_cam[i] = cam_from_receiver * mesh.vertices[i];
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const std::array<Eigen::Vector3d, 3> tri = {vertices_in_cam[static_cast<size_t>(t[0])],
                                                vertices_in_cam[static_cast<size_t>(t[1])],
                                                vertices_in_cam[static_cast<size_t>(t[2])]};
    if (tri[0].z() >= near_m && tri[1].z() >= near_m && tri[2].z() >= near_m) {
      RasterizeTriangle(tri[0], tri[1], tri[2], k, buffer);
      continue;
    }
    std::array<Eigen::Vector3d, 4> clipped;
    const int n = ClipNear(tri, near_m, clipped);
    for (int i = 1; i + 1 < n; ++i) {
      RasterizeTriangle(clipped[0], clipped[static_cast<size_t>(i)], clipped[static_cast<size_t>(i + 1)], k, buffer);
    }
  }
  return buffer;
}

// ---- PLY ----

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

}  // namespace

void ReferenceModelOptions::Check() const {
  if (num_points == 0) throw Error("reference model: num_points must be positive");
  if (!(depth_tolerance_m >= 0.0) || !std::isfinite(depth_tolerance_m)) {
    throw Error("reference model: depth_tolerance_m must be finite and >= 0");
  }
  if (neighbourhood_radius_px < 0 || neighbourhood_radius_px > 16) {
    throw Error("reference model: neighbourhood_radius_px must be in [0, 16]");
  }
  if (raster_width_px < 0 || raster_height_px < 0 || raster_width_px > 16384 || raster_height_px > 16384) {
    throw Error("reference model: raster size must be in [0, 16384] (0 = image size)");
  }
}

std::vector<Eigen::Vector3d> SampleSurface(const TriangleMesh& mesh, size_t num_points, uint64_t seed) {
  std::vector<double> cumulative_area(mesh.triangles.size());
  double total = 0.0;
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    total += TriangleArea(mesh, i);
    cumulative_area[i] = total;
  }
  if (!(total > 0.0) || !std::isfinite(total)) throw Error("SampleSurface: the mesh has no surface area");

  std::mt19937_64 generator(seed);
  std::vector<Eigen::Vector3d> points;
  points.reserve(num_points);
  for (size_t n = 0; n < num_points; ++n) {
    const double pick = Uniform01(generator) * total;
    const size_t i =
        std::min<size_t>(static_cast<size_t>(std::upper_bound(cumulative_area.begin(), cumulative_area.end(), pick) -
                                             cumulative_area.begin()),
                         cumulative_area.size() - 1);
    const double sqrt_r1 = std::sqrt(Uniform01(generator));
    const double r2 = Uniform01(generator);
    const Eigen::Vector3i& t = mesh.triangles[i];
    points.push_back((1.0 - sqrt_r1) * mesh.vertices[static_cast<size_t>(t[0])] +
                     sqrt_r1 * (1.0 - r2) * mesh.vertices[static_cast<size_t>(t[1])] +
                     sqrt_r1 * r2 * mesh.vertices[static_cast<size_t>(t[2])]);
  }
  return points;
}

ReferenceModel FullModel(const TriangleMesh& mesh, const ReferenceModelOptions& options) {
  options.Check();
  return {"full", SampleSurface(mesh, options.num_points, options.seed)};
}

Eigen::Isometry3d ShellTankerFromReceiver(const StereoRig& rig, const ReferenceModelOptions& options) {
  if (options.tanker_from_receiver) return IsometryFromPose(*options.tanker_from_receiver);
  Eigen::Isometry3d tanker_from_receiver = Eigen::Isometry3d::Identity();
  tanker_from_receiver.translation() = rig.contact_position_m;
  return tanker_from_receiver;
}

std::vector<bool> VisibleInCamera(const std::vector<Eigen::Vector3d>& points_in_receiver, const TriangleMesh& mesh,
                                  const Intrinsics& intrinsics, const Eigen::Isometry3d& cam_from_receiver,
                                  double near_m, const ReferenceModelOptions& options) {
  options.Check();
  const Intrinsics k =
      ScaledIntrinsics(intrinsics, options.raster_width_px > 0 ? options.raster_width_px : intrinsics.width_px,
                       options.raster_height_px > 0 ? options.raster_height_px : intrinsics.height_px);
  const DepthBuffer buffer = RasterizeDepth(mesh, k, cam_from_receiver, near_m);
  const int r = options.neighbourhood_radius_px;
  std::vector<bool> visible(points_in_receiver.size(), false);
  for (size_t i = 0; i < points_in_receiver.size(); ++i) {
    const Eigen::Vector3d p = cam_from_receiver * points_in_receiver[i];
    if (p.z() < near_m) continue;
    const auto pixel = k.Project(p);
    if (!pixel || !k.Contains(*pixel)) continue;
    const int px = static_cast<int>(std::floor(pixel->x() + 0.5));
    const int py = static_cast<int>(std::floor(pixel->y() + 0.5));
    for (int y = std::max(0, py - r); y <= std::min(buffer.height - 1, py + r) && !visible[i]; ++y) {
      for (int x = std::max(0, px - r); x <= std::min(buffer.width - 1, px + r); ++x) {
        if (p.z() <= static_cast<double>(buffer.At(x, y)) + options.depth_tolerance_m) {
          visible[i] = true;
          break;
        }
      }
    }
  }
  return visible;
}

ReferenceModel ShellModel(const std::vector<Eigen::Vector3d>& full_points, const TriangleMesh& mesh,
                          const StereoRig& rig, const ReferenceModelOptions& options) {
  const Eigen::Isometry3d tanker_from_receiver = ShellTankerFromReceiver(rig, options);
  const auto visible_in = [&](const Camera& camera) {
    return VisibleInCamera(full_points, mesh, camera.intrinsics,
                           camera.tanker_from_camera.inverse() * tanker_from_receiver, rig.near_m, options);
  };
  const std::vector<bool> left = visible_in(rig.left);
  const std::vector<bool> right = visible_in(rig.right);
  ReferenceModel shelled{"shelled", {}};
  for (size_t i = 0; i < full_points.size(); ++i) {
    if (options.require_both_cameras ? (left[i] && right[i]) : (left[i] || right[i])) {
      shelled.points_in_receiver.push_back(full_points[i]);
    }
  }
  return shelled;
}

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

  // Header: lines up to and including "end_header".
  size_t pos = 0;
  std::string format;
  std::vector<PlyElement> elements;
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
      words >> format >> version;
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian") {
        throw Error(at + ": unknown format '" + format + "'");
      }
    } else if (keyword == "element") {
      PlyElement element;
      long long count = -1;
      words >> element.name >> count;
      if (element.name.empty() || count < 0 || words.fail()) throw Error(at + ": malformed element line");
      element.count = static_cast<size_t>(count);
      elements.push_back(element);
    } else if (keyword == "property") {
      if (elements.empty()) throw Error(at + ": property before any element");
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
      elements.back().properties.push_back(property);
    } else if (keyword == "end_header") {
      ended = true;
      break;
    } else if (keyword != "comment" && keyword != "obj_info" && !keyword.empty()) {
      throw Error(at + ": unknown keyword '" + keyword + "'");
    }
  }
  if (!ended) throw Error(where + ": PLY header has no end_header line");
  if (format.empty()) throw Error(where + ": PLY header has no format line");

  // The vertex element and its x, y, z properties.
  size_t vertex_element = elements.size();
  for (size_t e = 0; e < elements.size(); ++e) {
    if (elements[e].name == "vertex") {
      vertex_element = e;
      break;
    }
  }
  if (vertex_element == elements.size()) throw Error(where + ": PLY file has no vertex element");
  const PlyElement& vertex = elements[vertex_element];
  std::array<int, 3> xyz = {-1, -1, -1};
  for (size_t p = 0; p < vertex.properties.size(); ++p) {
    for (int c = 0; c < 3; ++c) {
      if (vertex.properties[p].name == std::string(1, static_cast<char>('x' + c))) {
        xyz[static_cast<size_t>(c)] = static_cast<int>(p);
      }
    }
    if (vertex.properties[p].list) throw Error(where + ": list property in the vertex element is not supported");
  }
  if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0) throw Error(where + ": vertex element lacks x, y or z");

  std::vector<Eigen::Vector3d> points;
  points.reserve(vertex.count);
  if (format == "ascii") {
    std::istringstream data(bytes.substr(pos));
    std::string line;
    for (size_t e = 0; e < vertex_element; ++e) {  // earlier elements: one line per item
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
  } else {
    const bool swap = (format == "binary_little_endian") != MachineIsLittleEndian();
    for (size_t e = 0; e < vertex_element; ++e) {  // earlier elements: skip fixed-size items
      size_t item = 0;
      for (const PlyProperty& p : elements[e].properties) {
        if (p.list) throw Error(where + ": list property before the vertex element is not supported");
        item += static_cast<size_t>(p.size);
      }
      pos += item * elements[e].count;
    }
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
  }
  for (size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) throw Error(where + ": vertex " + std::to_string(i) + " is not finite");
  }
  return points;
}

}  // namespace aar
