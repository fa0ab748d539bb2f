#include "aar/analyzer/mesh.h"

#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <cstring>
#include <string>

#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/gltf_accessor.h"
#include "aar/gltf_scene.h"

namespace aar {
namespace {

// Images are never needed here; skipping their decoding keeps loading fast
// and independent of the image codecs tinygltf was built with.
bool SkipImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
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
  const GltfAccessor positions(model, position->second, where);
  if (positions.type() != TINYGLTF_TYPE_VEC3 || positions.component_type() != TINYGLTF_COMPONENT_TYPE_FLOAT) {
    throw Error(where + ": POSITION must be a float VEC3 accessor");
  }
  const size_t base = mesh.vertices.size();
  const Eigen::Matrix3d linear = body_from_node.topLeftCorner<3, 3>();
  const Eigen::Vector3d offset = body_from_node.topRightCorner<3, 1>();
  for (size_t i = 0; i < positions.count(); ++i) {
    const Eigen::Vector3d p(positions.Component(i, 0), positions.Component(i, 1), positions.Component(i, 2));
    if (!p.allFinite()) throw Error(where + ": POSITION holds a non-finite value");
    mesh.vertices.push_back(linear * p + offset);
  }

  std::vector<uint32_t> indices;
  if (primitive.indices >= 0) {
    indices = ReadGltfIndices(model, primitive.indices, where);
  } else {
    indices.resize(positions.count());
    for (size_t i = 0; i < positions.count(); ++i) indices[i] = static_cast<uint32_t>(i);
  }
  for (const uint32_t i : indices) {
    if (i >= positions.count()) throw Error(where + ": vertex index " + std::to_string(i) + " out of range");
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

// A .glb or .gltf file's bytes read from `where`; a .gltf's external buffers are looked up in `base_dir`.
TriangleMesh MeshFromGltf(const std::string& bytes, const std::string& where, const std::string& base_dir) {
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&SkipImage, nullptr);
  tinygltf::Model model;
  std::string err;
  std::string warn;
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const bool ok =
      bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0
          ? loader.LoadBinaryFromMemory(&model, &err, &warn, data, static_cast<unsigned int>(bytes.size()), base_dir)
          : loader.LoadASCIIFromString(&model, &err, &warn, bytes.data(), static_cast<unsigned int>(bytes.size()),
                                       base_dir);
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

}  // namespace

TriangleMesh LoadReceiverMesh(const std::filesystem::path& path) {
  CheckRegularFile(path, "receiver model file");
  return MeshFromGltf(ReadFileBytes(path), path.string(), path.parent_path().string());
}

TriangleMesh LoadInputMesh(const OpenedDataset& dataset, const std::string& name) {
  const std::string* bytes = dataset.Input(name);
  if (bytes == nullptr) throw Error(dataset.PathOf(name) + ": model file not found");
  return MeshFromGltf(*bytes, dataset.PathOf(name), dataset.folder().string());
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
