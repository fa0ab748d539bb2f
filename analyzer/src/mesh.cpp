#include "aar/analyzer/mesh.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>

#include <Eigen/Geometry>
#include <tiny_gltf.h>

#include "aar/error.h"
#include "aar/gltf_scene.h"

namespace aar {
namespace {

// Images are never needed here; skipping their decoding keeps loading fast
// and independent of the image codecs tinygltf was built with.
bool SkipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

// Bounds-checked view of an accessor's elements inside its buffer.
struct AccessorView {
  const unsigned char* data = nullptr;
  size_t stride = 0;
  size_t count = 0;
  int component_type = 0;
};

AccessorView ViewAccessor(const tinygltf::Model& model, int index, const std::string& where) {
  if (index < 0 || static_cast<size_t>(index) >= model.accessors.size()) {
    throw Error(where + ": accessor " + std::to_string(index) + " does not exist");
  }
  const tinygltf::Accessor& accessor = model.accessors[static_cast<size_t>(index)];
  if (accessor.sparse.isSparse) throw Error(where + ": sparse accessors are not supported");
  if (accessor.bufferView < 0 || static_cast<size_t>(accessor.bufferView) >= model.bufferViews.size()) {
    throw Error(where + ": accessor " + std::to_string(index) + " has no valid bufferView");
  }
  const tinygltf::BufferView& view = model.bufferViews[static_cast<size_t>(accessor.bufferView)];
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size()) {
    throw Error(where + ": bufferView " + std::to_string(accessor.bufferView) + " has no valid buffer");
  }
  const tinygltf::Buffer& buffer = model.buffers[static_cast<size_t>(view.buffer)];
  const int stride = accessor.ByteStride(view);
  const int element_size = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(accessor.componentType)) *
                           tinygltf::GetNumComponentsInType(static_cast<uint32_t>(accessor.type));
  if (stride <= 0 || element_size <= 0) throw Error(where + ": accessor " + std::to_string(index) + " is malformed");
  const size_t begin = view.byteOffset + accessor.byteOffset;
  const size_t needed = accessor.count == 0 ? 0 : (accessor.count - 1) * static_cast<size_t>(stride) + element_size;
  if (view.byteOffset + view.byteLength > buffer.data.size() || accessor.byteOffset + needed > view.byteLength) {
    throw Error(where + ": accessor " + std::to_string(index) + " reads past the end of its buffer");
  }
  return {buffer.data.data() + begin, static_cast<size_t>(stride), accessor.count, accessor.componentType};
}

std::vector<uint32_t> ReadIndices(const tinygltf::Model& model, int index, const std::string& where) {
  const AccessorView view = ViewAccessor(model, index, where);  // validates the index
  if (model.accessors[static_cast<size_t>(index)].type != TINYGLTF_TYPE_SCALAR) {
    throw Error(where + ": index accessor is not SCALAR");
  }
  std::vector<uint32_t> indices(view.count);
  for (size_t i = 0; i < view.count; ++i) {
    const unsigned char* p = view.data + i * view.stride;
    switch (view.component_type) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        indices[i] = *p;
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t v;
        std::memcpy(&v, p, sizeof(v));
        indices[i] = v;
        break;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        std::memcpy(&indices[i], p, sizeof(uint32_t));
        break;
      default:
        throw Error(where + ": index accessor has a non-integer component type");
    }
  }
  return indices;
}

// Appends one primitive's triangles, its vertices mapped by body_from_gltf_node.
void AppendPrimitive(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                     const Eigen::Matrix4d& body_from_node, const std::string& where, TriangleMesh& mesh) {
  const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
  if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
    return;  // points and lines have no surface
  }
  const auto position = primitive.attributes.find("POSITION");
  if (position == primitive.attributes.end()) throw Error(where + ": primitive without POSITION");
  const AccessorView view = ViewAccessor(model, position->second, where);  // validates the index
  const tinygltf::Accessor& accessor = model.accessors[static_cast<size_t>(position->second)];
  if (accessor.type != TINYGLTF_TYPE_VEC3 || view.component_type != TINYGLTF_COMPONENT_TYPE_FLOAT) {
    throw Error(where + ": POSITION must be a float VEC3 accessor");
  }
  const size_t base = mesh.vertices.size();
  const Eigen::Matrix3d linear = body_from_node.topLeftCorner<3, 3>();
  const Eigen::Vector3d offset = body_from_node.topRightCorner<3, 1>();
  for (size_t i = 0; i < view.count; ++i) {
    float xyz[3];
    std::memcpy(xyz, view.data + i * view.stride, sizeof(xyz));
    const Eigen::Vector3d p(xyz[0], xyz[1], xyz[2]);
    if (!p.allFinite()) throw Error(where + ": POSITION holds a non-finite value");
    mesh.vertices.push_back(linear * p + offset);
  }

  std::vector<uint32_t> indices;
  if (primitive.indices >= 0) {
    indices = ReadIndices(model, primitive.indices, where);
  } else {
    indices.resize(view.count);
    for (size_t i = 0; i < view.count; ++i) indices[i] = static_cast<uint32_t>(i);
  }
  for (const uint32_t i : indices) {
    if (i >= view.count) throw Error(where + ": vertex index " + std::to_string(i) + " out of range");
  }
  // A node transform with negative determinant mirrors the mesh; swapping two
  // corners keeps the winding counter-clockwise seen from outside.
  const bool mirrored = linear.determinant() < 0.0;
  auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
    if (a == b || b == c || a == c) return;  // degenerate (strip restarts)
    if (mirrored) std::swap(b, c);
    mesh.triangles.emplace_back(static_cast<int>(base + a), static_cast<int>(base + b), static_cast<int>(base + c));
  };
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    for (size_t i = 0; i + 2 < indices.size(); i += 3) add(indices[i], indices[i + 1], indices[i + 2]);
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t i = 0; i + 2 < indices.size(); ++i) {
      if (i % 2 == 0) {
        add(indices[i], indices[i + 1], indices[i + 2]);
      } else {  // odd triangles of a strip are wound the other way
        add(indices[i + 1], indices[i], indices[i + 2]);
      }
    }
  } else {  // fan
    for (size_t i = 1; i + 1 < indices.size(); ++i) add(indices[0], indices[i], indices[i + 1]);
  }
}

bool HasGlbMagic(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[4] = {};
  in.read(magic, 4);
  return in.gcount() == 4 && std::memcmp(magic, "glTF", 4) == 0;
}

}  // namespace

TriangleMesh LoadReceiverMesh(const std::filesystem::path& path) {
  const std::string where = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw Error(where + ": receiver model file not found");

  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&SkipImage, nullptr);
  tinygltf::Model model;
  std::string err;
  std::string warn;
  const bool ok = HasGlbMagic(path) ? loader.LoadBinaryFromFile(&model, &err, &warn, path.string())
                                    : loader.LoadASCIIFromFile(&model, &err, &warn, path.string());
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == '\r')) err.pop_back();
    throw Error(where + ": not a readable glTF file" + (err.empty() ? std::string() : " (" + err + ")"));
  }

  TriangleMesh mesh;
  ForEachMeshNode(model, where, [&](const tinygltf::Mesh& gltf_mesh, const Eigen::Matrix4d& body_from_node) {
    for (const tinygltf::Primitive& primitive : gltf_mesh.primitives) {
      AppendPrimitive(model, primitive, body_from_node, where, mesh);
    }
  });
  if (mesh.triangles.empty()) throw Error(where + ": the model holds no triangles");
  return mesh;
}

double TriangleArea(const TriangleMesh& mesh, size_t triangle) {
  const Eigen::Vector3i& t = mesh.triangles[triangle];
  const Eigen::Vector3d& a = mesh.vertices[static_cast<size_t>(t[0])];
  const Eigen::Vector3d& b = mesh.vertices[static_cast<size_t>(t[1])];
  const Eigen::Vector3d& c = mesh.vertices[static_cast<size_t>(t[2])];
  return 0.5 * (b - a).cross(c - a).norm();
}

double SurfaceArea(const TriangleMesh& mesh) {
  double area = 0.0;
  for (size_t i = 0; i < mesh.triangles.size(); ++i) area += TriangleArea(mesh, i);
  return area;
}

}  // namespace aar
