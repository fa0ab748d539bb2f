#pragma once
// Graphics pipeline set-up for the scene shaders, vkguide-style: the fixed
// state the renderer always uses (triangle lists of aar::Vertex, no culling
// since models are double-sided, reversed depth test, no blending; or the
// background's full-screen triangle) with the
// parts that vary per render target as fields, and one Build() call.

#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace aar {

/// A shader module from SPIR-V words; throws aar::Error naming the call on failure.
VkShaderModule CreateShaderModule(VkDevice device, const uint32_t* code, size_t bytes);

/// Specialization constants, 32 bits each: ids 0, 1, 2, ... in the order added, or given.
class SpecializationConstants {
 public:
  /// The next constant id: one after the last added (0 for the first).
  void AddFloat(float value);
  void AddInt(int32_t value);
  /// A constant of a given id, leaving the ids between unset (the shader's defaults).
  void AddFloatAt(uint32_t id, float value);
  void AddIntAt(uint32_t id, int32_t value);
  bool empty() const { return entries_.empty(); }
  /// Valid while this object lives and nothing is added.
  const VkSpecializationInfo* Info();

 private:
  std::vector<VkSpecializationMapEntry> entries_;
  std::vector<uint32_t> words_;
  VkSpecializationInfo info_{};
};

struct PipelineBuilder {
  VkShaderModule vertex_shader = VK_NULL_HANDLE;
  VkShaderModule fragment_shader = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;  ///< rasterization samples (the target's)
  uint32_t width = 1;                                     ///< viewport and scissor width [px]
  uint32_t height = 1;                                    ///< viewport and scissor height [px]
  /// false: no vertex buffer and no depth test or write (the background's
  /// full-screen triangle, drawn first, behind everything).
  bool scene_geometry = true;
  const VkSpecializationInfo* fragment_specialization = nullptr;  ///< fragment-shader constants (or none)

  /// Creates the pipeline for subpass 0 of `render_pass`; the caller owns it.
  VkPipeline Build(VkDevice device, VkRenderPass render_pass) const;
};

}  // namespace aar
