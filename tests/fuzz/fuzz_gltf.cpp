// libFuzzer harness: glTF loading by the analyzer (analyzer/mesh.h: triangles)
// and the renderer (renderer/scene_model.h: vertices, normals, textures),
// binary (.glb, by its magic) or JSON (.gltf).
#include <cstring>

#include "aar/analyzer/mesh.h"
#include "aar/error.h"
#include "aar/renderer/scene_model.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const std::filesystem::path path = aar::fuzz::WriteInput(data, size, binary ? "model.glb" : "model.gltf");
  try {
    aar::LoadReceiverMesh(path);
  } catch (const aar::Error&) {
  }
  try {
    aar::LoadSceneModel(path);
  } catch (const aar::Error&) {
  }
  return 0;
}
