#pragma once
// Move-only owners of Vulkan buffers and images with their memory.

#include <vulkan/vulkan.h>

#include <cstddef>

#include "aar/renderer/vulkan_context.h"

namespace aar {

class GpuBuffer {
 public:
  GpuBuffer() = default;
  /// A buffer of `size` bytes; host-visible buffers are HOST_COHERENT and stay mapped (`mapped()`).
  GpuBuffer(VulkanContext& context, VkDeviceSize size, VkBufferUsageFlags usage, bool host_visible);
  ~GpuBuffer();
  GpuBuffer(GpuBuffer&& other) noexcept;
  GpuBuffer& operator=(GpuBuffer&& other) noexcept;
  GpuBuffer(const GpuBuffer&) = delete;
  GpuBuffer& operator=(const GpuBuffer&) = delete;

  VkBuffer buffer() const { return buffer_; }
  void* mapped() const { return mapped_; }
  VkDeviceSize size() const { return size_; }

 private:
  void Reset();
  VkDevice device_ = VK_NULL_HANDLE;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  void* mapped_ = nullptr;
  VkDeviceSize size_ = 0;
};

struct GpuImageDesc {
  uint32_t width = 1;
  uint32_t height = 1;
  uint32_t mip_levels = 1;
  VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
  VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;
  VkImageUsageFlags usage = 0;
  VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT;
};

class GpuImage {
 public:
  GpuImage() = default;
  GpuImage(VulkanContext& context, const GpuImageDesc& desc);
  ~GpuImage();
  GpuImage(GpuImage&& other) noexcept;
  GpuImage& operator=(GpuImage&& other) noexcept;
  GpuImage(const GpuImage&) = delete;
  GpuImage& operator=(const GpuImage&) = delete;

  VkImage image() const { return image_; }
  VkImageView view() const { return view_; }
  const GpuImageDesc& desc() const { return desc_; }

 private:
  void Reset();
  VkDevice device_ = VK_NULL_HANDLE;
  VkImage image_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
  GpuImageDesc desc_;
};

/// Records a full-image layout transition with a conservative barrier.
void TransitionImage(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, uint32_t mip_levels,
                     VkImageLayout from, VkImageLayout to);

}  // namespace aar
