#pragma once
// Reading glTF 2.0 accessors (tinygltf) with every index and byte range
// checked; shared by the renderer's and the analyzer's model loaders, next to
// the scene walker (gltf_scene.h).

#include <tiny_gltf.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace aar {

/// A bounds-checked view of one accessor's elements inside its buffer.
class GltfAccessor {
 public:
  /// Throws aar::Error prefixed by `where` (the file) when the accessor does
  /// not exist, is sparse, has no valid buffer view or buffer, is malformed,
  /// or reads past the end of its buffer view or buffer.
  GltfAccessor(const tinygltf::Model& model, int index, const std::string& where);

  size_t count() const { return count_; }
  int type() const { return type_; }                      ///< TINYGLTF_TYPE_*
  int component_type() const { return component_type_; }  ///< TINYGLTF_COMPONENT_TYPE_*
  int components() const { return components_; }          ///< per element (1 SCALAR .. 16 MAT4)
  bool normalized() const { return normalized_; }

  /// Component c of element i: a float as is, an integer as its value, or a
  /// normalized integer mapped to [0, 1] (unsigned) or [-1, 1] (signed), as
  /// glTF 2.0 section 3.11 defines.
  double Component(size_t i, int c) const;

 private:
  const unsigned char* data_ = nullptr;
  size_t stride_ = 0;
  size_t count_ = 0;
  int type_ = 0;
  int component_type_ = 0;
  int component_size_ = 0;
  int components_ = 0;
  bool normalized_ = false;
};

/// The elements of an index accessor (SCALAR of unsigned byte, short or int,
/// not normalized).
/// Throws aar::Error prefixed by `where` for any other accessor.
std::vector<uint32_t> ReadGltfIndices(const tinygltf::Model& model, int index, const std::string& where);

}  // namespace aar
