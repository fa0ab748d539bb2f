#include "aar/renderer/scene_model.h"

#include <tiny_gltf.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>

#include "aar/error.h"
#include "aar/file_io.h"
#include "aar/gltf_accessor.h"
#include "aar/gltf_scene.h"

namespace aar {
namespace {

// The primitive's vertices, from its node's frame into the body frame; the
// normal +z and the uv 0 where NORMAL or TEXCOORD_0 has no element.
std::vector<Vertex> BodyVertices(const GltfAccessor& positions, const std::optional<GltfAccessor>& normals,
                                 const std::optional<GltfAccessor>& uvs, const Eigen::Matrix4d& body_from_node) {
  std::vector<Vertex> vertices;
  const Eigen::Matrix3d linear = body_from_node.topLeftCorner<3, 3>();
  const Eigen::Matrix3d normal_matrix = linear.inverse().transpose();
  vertices.resize(positions.count());
  for (size_t i = 0; i < positions.count(); ++i) {
    const Eigen::Vector3d x =
        linear * Eigen::Vector3d(positions.Component(i, 0), positions.Component(i, 1), positions.Component(i, 2)) +
        body_from_node.topRightCorner<3, 1>();
    Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
    if (normals && i < normals->count()) {
      n = (normal_matrix *
           Eigen::Vector3d(normals->Component(i, 0), normals->Component(i, 1), normals->Component(i, 2)));
      if (n.norm() > 0) n.normalize();
    }
    Vertex& v = vertices[i];
    for (int c = 0; c < 3; ++c) {
      v.position[c] = static_cast<float>(x(c));
      v.normal[c] = static_cast<float>(n(c));
    }
    v.uv[0] = uvs && i < uvs->count() ? static_cast<float>(uvs->Component(i, 0)) : 0.0f;
    v.uv[1] = uvs && i < uvs->count() ? static_cast<float>(uvs->Component(i, 1)) : 0.0f;
  }
  return vertices;
}

// The primitive's triangle list: its indices (checked against vertex_count),
// or 0 .. vertex_count - 1 without them, cut to whole triangles.
std::vector<uint32_t> TriangleIndices(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                                      size_t vertex_count, const std::string& where) {
  std::vector<uint32_t> indices;
  if (prim.indices >= 0) {
    indices = ReadGltfIndices(model, prim.indices, where);
    for (const uint32_t index : indices) {
      if (index >= vertex_count) throw Error(where + ": index out of range");
    }
  } else {
    indices.resize(vertex_count);
    for (size_t i = 0; i < indices.size(); ++i) indices[i] = static_cast<uint32_t>(i);
  }
  indices.resize(indices.size() / 3 * 3);
  return indices;
}

// Flat normals from the faces, accumulated per vertex.
void SetFlatNormals(Primitive& p) {
  std::vector<Eigen::Vector3d> acc(p.vertices.size(), Eigen::Vector3d::Zero());
  for (size_t t = 0; t < p.indices.size(); t += 3) {
    Eigen::Vector3f a(p.vertices[p.indices[t]].position), b(p.vertices[p.indices[t + 1]].position),
        c(p.vertices[p.indices[t + 2]].position);
    const Eigen::Vector3d n = ((b - a).cross(c - a)).cast<double>();
    for (int k = 0; k < 3; ++k) acc[p.indices[t + k]] += n;
  }
  for (size_t i = 0; i < acc.size(); ++i) {
    const Eigen::Vector3d n = acc[i].norm() > 0 ? acc[i].normalized() : Eigen::Vector3d::UnitZ();
    for (int c = 0; c < 3; ++c) p.vertices[i].normal[c] = static_cast<float>(n(c));
  }
}

// Image `source` of the model as texture mips; throws naming it unless it is a decodable 8-bit image.
TextureMips MipsOfImage(const tinygltf::Model& model, int source, const std::string& where) {
  const tinygltf::Image& image = model.images[source];
  if (image.bits != 8 || image.width <= 0 || image.height <= 0 || image.image.empty()) {
    throw Error(where + ": image " + std::to_string(source) + " is not a decodable 8-bit image");
  }
  // Expand grey, grey+alpha and RGB to RGBA.
  const int comp = image.component;
  const size_t pixels = static_cast<size_t>(image.width) * image.height;
  std::vector<uint8_t> rgba(pixels * 4, 255);
  for (size_t px = 0; px < pixels; ++px) {
    const uint8_t* src = &image.image[px * comp];
    uint8_t* dst = &rgba[px * 4];
    for (int c = 0; c < 3; ++c) dst[c] = comp >= 3 ? src[c] : src[0];
    if (comp == 2 || comp == 4) dst[3] = src[comp - 1];
  }
  return BuildMips(std::move(rgba), image.width, image.height);
}

// The base colour factor and texture of the primitive's material; each image
// becomes one texture of `out`, the first time a primitive uses it.
void ApplyMaterial(const tinygltf::Model& model, const tinygltf::Primitive& prim, const std::string& where,
                   std::vector<int>& texture_of_image, SceneModel& out, Primitive& p) {
  if (prim.material < 0 || prim.material >= static_cast<int>(model.materials.size())) return;
  const tinygltf::PbrMetallicRoughness& pbr = model.materials[prim.material].pbrMetallicRoughness;
  for (int c = 0; c < 4 && c < static_cast<int>(pbr.baseColorFactor.size()); ++c) {
    p.base_color_factor[c] = static_cast<float>(pbr.baseColorFactor[c]);
  }
  p.metallic = static_cast<float>(pbr.metallicFactor);
  p.roughness = static_cast<float>(pbr.roughnessFactor);
  if (!(p.metallic >= 0.0f && p.metallic <= 1.0f) || !(p.roughness >= 0.0f && p.roughness <= 1.0f)) {
    throw Error(where + ": material '" + model.materials[prim.material].name +
                "' has metallicFactor or roughnessFactor outside [0, 1]");
  }
  const int texture = pbr.baseColorTexture.index;
  if (texture < 0 || texture >= static_cast<int>(model.textures.size())) return;
  const int source = model.textures[texture].source;
  if (source < 0 || source >= static_cast<int>(model.images.size())) throw Error(where + ": texture without image");
  if (texture_of_image[source] < 0) {
    TextureMips mips = MipsOfImage(model, source, where);
    texture_of_image[source] = static_cast<int>(out.textures.size());
    out.textures.push_back(std::move(mips));
  }
  p.texture = texture_of_image[source];
}

void AppendPrimitive(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                     const Eigen::Matrix4d& body_from_node, const std::string& where,
                     std::vector<int>& texture_of_image, SceneModel& out) {
  if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) return;  // points and lines are not rendered
  const auto position = prim.attributes.find("POSITION");
  if (position == prim.attributes.end()) throw Error(where + ": primitive without POSITION");
  const GltfAccessor positions(model, position->second, where);
  std::optional<GltfAccessor> normals, uvs;
  if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) normals.emplace(model, it->second, where);
  if (auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) uvs.emplace(model, it->second, where);
  if (positions.type() != TINYGLTF_TYPE_VEC3 || (normals && normals->type() != TINYGLTF_TYPE_VEC3) ||
      (uvs && uvs->type() != TINYGLTF_TYPE_VEC2)) {
    throw Error(where + ": POSITION and NORMAL must be VEC3 accessors, TEXCOORD_0 a VEC2 accessor");
  }

  Primitive p;
  p.vertices = BodyVertices(positions, normals, uvs, body_from_node);
  p.indices = TriangleIndices(model, prim, p.vertices.size(), where);
  if (p.indices.empty()) return;
  if (!normals) SetFlatNormals(p);
  ApplyMaterial(model, prim, where, texture_of_image, out, p);
  out.primitives.push_back(std::move(p));
}

}  // namespace

float SrgbToLinear(float s) { return s <= 0.04045f ? s / 12.92f : std::pow((s + 0.055f) / 1.055f, 2.4f); }

float LinearToSrgb(float l) {
  l = std::clamp(l, 0.0f, 1.0f);
  return l <= 0.0031308f ? 12.92f * l : 1.055f * std::pow(l, 1.0f / 2.4f) - 0.055f;
}

uint8_t LinearToSrgb8(float linear) { return static_cast<uint8_t>(std::lround(LinearToSrgb(linear) * 255.0f)); }

TextureMips BuildMips(std::vector<uint8_t> rgba, int width, int height) {
  TextureMips mips;
  float to_linear[256];
  for (int i = 0; i < 256; ++i) to_linear[i] = SrgbToLinear(i / 255.0f);
  mips.levels.push_back(std::move(rgba));
  mips.sizes.push_back({width, height});
  while (width > 1 || height > 1) {
    const int w2 = std::max(1, width / 2);
    const int h2 = std::max(1, height / 2);
    const std::vector<uint8_t>& src = mips.levels.back();
    std::vector<uint8_t> dst(static_cast<size_t>(w2) * h2 * 4);
    for (int y = 0; y < h2; ++y) {
      for (int x = 0; x < w2; ++x) {
        const int x0 = std::min(2 * x, width - 1), x1 = std::min(2 * x + 1, width - 1);
        const int y0 = std::min(2 * y, height - 1), y1 = std::min(2 * y + 1, height - 1);
        for (int c = 0; c < 4; ++c) {
          auto at = [&](int xx, int yy) { return src[(static_cast<size_t>(yy) * width + xx) * 4 + c]; };
          if (c == 3) {
            dst[(static_cast<size_t>(y) * w2 + x) * 4 + c] =
                static_cast<uint8_t>((at(x0, y0) + at(x1, y0) + at(x0, y1) + at(x1, y1) + 2) / 4);
          } else {
            const float mean =
                0.25f * (to_linear[at(x0, y0)] + to_linear[at(x1, y0)] + to_linear[at(x0, y1)] + to_linear[at(x1, y1)]);
            dst[(static_cast<size_t>(y) * w2 + x) * 4 + c] = LinearToSrgb8(mean);
          }
        }
      }
    }
    mips.levels.push_back(std::move(dst));
    mips.sizes.push_back({w2, h2});
    width = w2;
    height = h2;
  }
  return mips;
}

std::vector<Eigen::Vector3d> SceneModel::AllPositions() const {
  std::vector<Eigen::Vector3d> positions;
  for (const Primitive& p : primitives) {
    for (const Vertex& v : p.vertices) positions.emplace_back(v.position[0], v.position[1], v.position[2]);
  }
  return positions;
}

SceneModel LoadSceneModel(const std::filesystem::path& path) {
  const std::string where = path.string();
  CheckRegularFile(path, "model file");
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string error, warning;
  const bool binary = path.extension() == ".glb";
  const bool ok = binary ? loader.LoadBinaryFromFile(&model, &error, &warning, where)
                         : loader.LoadASCIIFromFile(&model, &error, &warning, where);
  if (!ok) {
    std::string reason = error.empty() ? "unknown error" : error;
    std::replace(reason.begin(), reason.end(), '\n', ' ');
    throw Error(where + ": not a valid glTF 2.0 file (" + reason + ")");
  }
  SceneModel out;
  out.path = path;
  std::vector<int> texture_of_image(model.images.size(), -1);
  ForEachMeshNode(model, where, [&](const tinygltf::Mesh& mesh, const Eigen::Matrix4d& body_from_node) {
    const size_t first = out.primitives.size();
    for (const tinygltf::Primitive& prim : mesh.primitives) {
      AppendPrimitive(model, prim, body_from_node, where, texture_of_image, out);
    }
    for (size_t i = first; i < out.primitives.size(); ++i) out.primitives[i].mesh = mesh.name;
  });
  if (out.primitives.empty()) throw Error(where + ": model has no triangles");
  return out;
}

}  // namespace aar
