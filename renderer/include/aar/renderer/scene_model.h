#pragma once
// A glTF 2.0 model loaded for rendering (pure CPU data, no Vulkan): triangle
// primitives in the model's body frame (x forward, y left, z up; node
// transforms and body_from_gltf applied), their materials, and textures with a
// full mip chain built on the CPU in linear colour (deterministic).

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace aar {

struct Vertex {
  float position[3];  ///< body frame [m]
  float normal[3];    ///< body frame, unit
  float uv[2];        ///< TEXCOORD_0 (0 when absent)
};

struct TextureMips {
  /// levels[0] is the full image; each level is RGBA8 sRGB, rows top to bottom.
  std::vector<std::vector<uint8_t>> levels;
  std::vector<std::array<int, 2>> sizes;  ///< width, height per level
};

struct Primitive {
  std::vector<Vertex> vertices;
  std::vector<uint32_t> indices;
  std::array<float, 4> base_color_factor = {1, 1, 1, 1};  ///< linear RGBA
  int texture = -1;                                       ///< index into SceneModel::textures, -1 for none
  float metallic = 1.0f;   ///< glTF metallicFactor (its default 1 when the material omits it)
  float roughness = 1.0f;  ///< glTF roughnessFactor (perceptual roughness; default 1)
  /// A light: base_color_factor's RGB is its radiance, unlit (receiver_lights.h).
  bool emissive = false;
  std::string mesh;  ///< the glTF mesh's name (the scene generators name it after its part: "nacelle_left", ...)
};

struct SceneModel {
  std::filesystem::path path;
  std::vector<Primitive> primitives;
  std::vector<TextureMips> textures;

  /// Every vertex position (body frame), for visibility checks.
  std::vector<Eigen::Vector3d> AllPositions() const;
};

/// Loads a .glb or .gltf file. Throws aar::Error naming the file when it is
/// missing, not glTF, or holds no triangles.
SceneModel LoadSceneModel(const std::filesystem::path& path);

/// Builds the mip chain of an RGBA8 sRGB image by 2x2 box filtering in linear
/// colour (odd sizes: the last row/column is repeated).
TextureMips BuildMips(std::vector<uint8_t> rgba, int width, int height);

/// sRGB transfer functions, exact formulas (IEC 61966-2-1).
float SrgbToLinear(float srgb);
float LinearToSrgb(float linear);
/// 8-bit encoding of a linear value in [0,1] with round-to-nearest.
uint8_t LinearToSrgb8(float linear);

}  // namespace aar
