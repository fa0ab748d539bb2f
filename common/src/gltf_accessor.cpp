#include "aar/gltf_accessor.h"

#include <algorithm>
#include <cstring>

#include "aar/error.h"

namespace aar {

GltfAccessor::GltfAccessor(const tinygltf::Model& model, int index, const std::string& where) {
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
  component_size_ = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(accessor.componentType));
  components_ = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(accessor.type));
  if (stride <= 0 || component_size_ <= 0 || components_ <= 0) {
    throw Error(where + ": accessor " + std::to_string(index) + " is malformed");
  }
  // Every sum and product is checked: a huge `count` or offset must not wrap
  // around and pass the bounds test.
  const size_t element_size = static_cast<size_t>(component_size_) * static_cast<size_t>(components_);
  const std::string past_end = where + ": accessor " + std::to_string(index) + " reads past the end of its buffer";
  size_t view_end = 0;
  if (__builtin_add_overflow(view.byteOffset, view.byteLength, &view_end) || view_end > buffer.data.size()) {
    throw Error(past_end);
  }
  size_t needed = 0;
  if (accessor.count > 0 && (__builtin_mul_overflow(accessor.count - 1, static_cast<size_t>(stride), &needed) ||
                             __builtin_add_overflow(needed, element_size, &needed))) {
    throw Error(past_end + " (count " + std::to_string(accessor.count) + ")");
  }
  size_t accessor_end = 0;
  if (__builtin_add_overflow(accessor.byteOffset, needed, &accessor_end) || accessor_end > view.byteLength) {
    throw Error(past_end);
  }
  data_ = buffer.data.data() + view.byteOffset + accessor.byteOffset;
  stride_ = static_cast<size_t>(stride);
  count_ = accessor.count;
  type_ = accessor.type;
  component_type_ = accessor.componentType;
  normalized_ = accessor.normalized;
}

double GltfAccessor::Component(size_t i, int c) const {
  const unsigned char* p = data_ + i * stride_ + static_cast<size_t>(c) * static_cast<size_t>(component_size_);
  switch (component_type_) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return normalized_ ? v / 4294967295.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalized_ ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return normalized_ ? *p / 255.0 : *p;
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalized_ ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalized_ ? std::max(v / 127.0, -1.0) : v;
    }
    default:
      return 0.0;
  }
}

std::vector<uint32_t> ReadGltfIndices(const tinygltf::Model& model, int index, const std::string& where) {
  const GltfAccessor accessor(model, index, where);  // validates the index
  if (accessor.type() != TINYGLTF_TYPE_SCALAR) throw Error(where + ": index accessor is not SCALAR");
  const int type = accessor.component_type();
  if (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
    throw Error(where + ": index accessor has a non-integer component type");
  }
  if (accessor.normalized()) throw Error(where + ": index accessor is normalized");
  std::vector<uint32_t> indices(accessor.count());
  for (size_t i = 0; i < indices.size(); ++i) indices[i] = static_cast<uint32_t>(accessor.Component(i, 0));
  return indices;
}

}  // namespace aar
