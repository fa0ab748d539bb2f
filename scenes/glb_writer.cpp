#include "glb_writer.h"

#include <tiny_gltf.h>

#include <cstring>
#include <limits>

#include "aar/error.h"

namespace aar::scenes {
namespace {

/// Appends raw bytes to buffer 0 as a new buffer view (4-byte aligned); returns its index.
int AddBufferView(tinygltf::Model& model, const void* data, std::size_t size, int target) {
  auto& bytes = model.buffers[0].data;
  while (bytes.size() % 4 != 0) bytes.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = bytes.size();
  view.byteLength = size;
  view.target = target;
  const auto* p = static_cast<const std::uint8_t*>(data);
  bytes.insert(bytes.end(), p, p + size);
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size()) - 1;
}

int AddAccessor(tinygltf::Model& model, int view, int component_type, int type, std::size_t count,
                std::vector<double> min = {}, std::vector<double> max = {}) {
  tinygltf::Accessor accessor;
  accessor.bufferView = view;
  accessor.componentType = component_type;
  accessor.type = type;
  accessor.count = count;
  accessor.minValues = std::move(min);
  accessor.maxValues = std::move(max);
  model.accessors.push_back(accessor);
  return static_cast<int>(model.accessors.size()) - 1;
}

int AddVec3(tinygltf::Model& model, const std::vector<Vec3>& body, bool with_bounds) {
  std::vector<float> data;
  data.reserve(body.size() * 3);
  std::vector<double> lo(3, std::numeric_limits<double>::infinity()), hi(3, -std::numeric_limits<double>::infinity());
  for (const Vec3& p : body) {
    const Vec3 g = GltfFromBody(p);
    for (int k = 0; k < 3; ++k) {
      const float f = static_cast<float>(g[k]);
      data.push_back(f);
      lo[static_cast<std::size_t>(k)] = std::min(lo[static_cast<std::size_t>(k)], static_cast<double>(f));
      hi[static_cast<std::size_t>(k)] = std::max(hi[static_cast<std::size_t>(k)], static_cast<double>(f));
    }
  }
  const int view = AddBufferView(model, data.data(), data.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
  if (!with_bounds) return AddAccessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, body.size());
  return AddAccessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, body.size(), lo, hi);
}

tinygltf::Primitive MakePrimitive(tinygltf::Model& model, const Primitive& prim) {
  const Mesh& mesh = prim.mesh;
  if (mesh.normals.size() != mesh.positions.size() || (!mesh.uvs.empty() && mesh.uvs.size() != mesh.positions.size())) {
    throw Error("WriteGlb: attribute count mismatch");
  }
  tinygltf::Primitive out;
  out.mode = TINYGLTF_MODE_TRIANGLES;
  out.material = prim.material;
  out.attributes["POSITION"] = AddVec3(model, mesh.positions, true);
  out.attributes["NORMAL"] = AddVec3(model, mesh.normals, false);
  if (!mesh.uvs.empty()) {
    std::vector<float> uv;
    uv.reserve(mesh.uvs.size() * 2);
    for (const Vec2& t : mesh.uvs) {
      uv.push_back(static_cast<float>(t.x()));
      uv.push_back(static_cast<float>(t.y()));
    }
    const int view = AddBufferView(model, uv.data(), uv.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
    out.attributes["TEXCOORD_0"] =
        AddAccessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, mesh.uvs.size());
  }
  int view = 0, component = 0;
  if (mesh.positions.size() <= 65535) {
    const std::vector<std::uint16_t> idx(mesh.indices.begin(), mesh.indices.end());
    view = AddBufferView(model, idx.data(), idx.size() * 2, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    component = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  } else {
    view = AddBufferView(model, mesh.indices.data(), mesh.indices.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    component = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
  }
  out.indices = AddAccessor(model, view, component, TINYGLTF_TYPE_SCALAR, mesh.indices.size());
  return out;
}

}  // namespace

void WriteGlb(const SceneModel& scene, const std::filesystem::path& path) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "aar-make-scenes";
  model.buffers.resize(1);

  if (!scene.texture_png.empty()) {
    tinygltf::Image image;
    image.name = scene.name + "_atlas";
    image.mimeType = "image/png";
    image.bufferView = AddBufferView(model, scene.texture_png.data(), scene.texture_png.size(), 0);
    model.images.push_back(image);
    tinygltf::Sampler sampler;
    sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
    sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
    sampler.wrapS = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;  // atlas: never wrap across islands
    sampler.wrapT = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
    model.samplers.push_back(sampler);
    tinygltf::Texture texture;
    texture.source = 0;
    texture.sampler = 0;
    model.textures.push_back(texture);
  }
  for (const Material& m : scene.materials) {
    if (m.textured && scene.texture_png.empty()) throw Error("WriteGlb: textured material without texture");
    tinygltf::Material out;
    out.name = m.name;
    out.pbrMetallicRoughness.baseColorFactor = {m.base_color.begin(), m.base_color.end()};
    if (!(m.metallic >= 0.0 && m.metallic <= 1.0) || !(m.roughness >= 0.0 && m.roughness <= 1.0)) {
      throw Error("WriteGlb: material " + m.name + " has metallic or roughness outside [0, 1]");
    }
    out.pbrMetallicRoughness.metallicFactor = m.metallic;
    out.pbrMetallicRoughness.roughnessFactor = m.roughness;
    if (m.textured) out.pbrMetallicRoughness.baseColorTexture.index = 0;
    out.doubleSided = true;
    model.materials.push_back(out);
  }
  tinygltf::Scene gltf_scene;
  gltf_scene.name = scene.name;
  for (const Node& node : scene.nodes) {
    tinygltf::Mesh mesh;
    mesh.name = node.name;
    for (const Primitive& prim : node.primitives) mesh.primitives.push_back(MakePrimitive(model, prim));
    model.meshes.push_back(mesh);
    tinygltf::Node out;
    out.name = node.name;
    out.mesh = static_cast<int>(model.meshes.size()) - 1;
    model.nodes.push_back(out);
    gltf_scene.nodes.push_back(static_cast<int>(model.nodes.size()) - 1);
  }
  model.scenes.push_back(gltf_scene);
  model.defaultScene = 0;
  while (model.buffers[0].data.size() % 4 != 0) model.buffers[0].data.push_back(0);

  std::filesystem::path tmp = path;
  tmp += ".tmp";
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToFile(&model, tmp.string(), true, true, false, true)) {
    throw Error("WriteGlb: cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, path);
}

}  // namespace aar::scenes
