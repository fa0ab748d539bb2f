// Scene description handed to the glTF writer, and the writer itself
// (binary glTF 2.0 through tinygltf; geometry converted from body to glTF axes).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "geometry.h"

namespace aar::scenes {

/// glTF metallic-roughness material, double sided (docs/scenes.md,
/// "Materials", gives each model's values and where they come from).
struct Material {
  std::string name;
  std::array<double, 4> base_color{1.0, 1.0, 1.0, 1.0};  ///< baseColorFactor
  bool textured = false;                                 ///< uses the scene's texture as baseColorTexture
  double metallic = 0.0;                                 ///< metallicFactor: 0 dielectric (paint), 1 bare metal
  double roughness = 0.8;                                ///< roughnessFactor (perceptual): 0 mirror, 0.8 matte
};

struct Primitive {
  Mesh mesh;  ///< body axes
  int material = 0;
};

/// A node with an identity transform (geometry is baked into the vertices).
struct Node {
  std::string name;
  std::vector<Primitive> primitives;
};

struct SceneModel {
  std::string name;
  std::vector<Material> materials;
  std::vector<Node> nodes;
  std::vector<std::uint8_t> texture_png;  ///< empty: no texture
};

/// Writes `scene` as a .glb to `path` (through a temporary file renamed into
/// place). The output depends only on `scene`.
void WriteGlb(const SceneModel& scene, const std::filesystem::path& path);

}  // namespace aar::scenes
