#pragma once
// The images one view is rendered into, with their render pass and
// framebuffer: a colour attachment (multisampled when samples > 1), a depth
// attachment (reversed depth, cleared to 0) and, when multisampled, a
// single-sample resolve image. The output (colour or resolve) ends the pass in
// TRANSFER_SRC_OPTIMAL, ready to be copied to host memory.

#include <vulkan/vulkan.h>

#include <cstdint>

#include "aar/renderer/gpu_resources.h"
#include "aar/renderer/vulkan_context.h"

namespace aar {

inline constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

class RenderTarget {
 public:
  RenderTarget(VulkanContext& context, uint32_t width, uint32_t height, int samples, VkFormat color_format);
  ~RenderTarget();
  RenderTarget(const RenderTarget&) = delete;
  RenderTarget& operator=(const RenderTarget&) = delete;

  int samples() const { return samples_; }
  VkRenderPass render_pass() const { return render_pass_; }
  VkFramebuffer framebuffer() const { return framebuffer_; }
  /// The single-sample image holding the rendered view after the pass.
  const GpuImage& Output() const { return samples_ > 1 ? resolve_ : color_; }

 private:
  VkDevice device_ = VK_NULL_HANDLE;
  int samples_ = 1;
  GpuImage color_;  // multisampled when samples > 1
  GpuImage depth_;
  GpuImage resolve_;  // single-sample copy source when samples > 1
  VkRenderPass render_pass_ = VK_NULL_HANDLE;
  VkFramebuffer framebuffer_ = VK_NULL_HANDLE;
};

}  // namespace aar
