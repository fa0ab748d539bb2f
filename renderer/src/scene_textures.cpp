// Textures on the GPU: a CPU-built mip chain uploaded into an optimal-tiling
// sRGB image, with the descriptor set (set 0) that binds it for the scene
// shaders.

#include <cstring>
#include <string>

#include "aar/error.h"
#include "aar/renderer/scene_renderer.h"

namespace aar {

void SceneRenderer::UploadTexture(const TextureMips& mips) {
  if (texture_sets_.size() >= kMaxTextures)
    throw Error("too many textures (limit " + std::to_string(kMaxTextures) + ")");
  VkDeviceSize total = 0;
  for (const auto& level : mips.levels) total += level.size();
  GpuBuffer staging(context_, total, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
  std::vector<VkBufferImageCopy> copies;
  VkDeviceSize offset = 0;
  for (size_t l = 0; l < mips.levels.size(); ++l) {
    std::memcpy(static_cast<uint8_t*>(staging.mapped()) + offset, mips.levels[l].data(), mips.levels[l].size());
    VkBufferImageCopy copy{};
    copy.bufferOffset = offset;
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, static_cast<uint32_t>(l), 0, 1};
    copy.imageExtent = {static_cast<uint32_t>(mips.sizes[l][0]), static_cast<uint32_t>(mips.sizes[l][1]), 1};
    copies.push_back(copy);
    offset += mips.levels[l].size();
  }
  GpuImageDesc desc;
  desc.width = mips.sizes[0][0];
  desc.height = mips.sizes[0][1];
  desc.mip_levels = static_cast<uint32_t>(mips.levels.size());
  desc.format = VK_FORMAT_R8G8B8A8_SRGB;
  desc.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
  GpuImage image(context_, desc);
  context_.SubmitAndWait([&](VkCommandBuffer cmd) {
    TransitionImage(cmd, image.image(), VK_IMAGE_ASPECT_COLOR_BIT, desc.mip_levels, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    vkCmdCopyBufferToImage(cmd, staging.buffer(), image.image(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                           static_cast<uint32_t>(copies.size()), copies.data());
    TransitionImage(cmd, image.image(), VK_IMAGE_ASPECT_COLOR_BIT, desc.mip_levels,
                    VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  });
  VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  alloc.descriptorPool = descriptor_pool_;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &set_layout_;
  VkDescriptorSet set = VK_NULL_HANDLE;
  VkCheck(vkAllocateDescriptorSets(context_.device(), &alloc, &set), "vkAllocateDescriptorSets");
  VkDescriptorImageInfo image_info{sampler_, image.view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
  write.dstSet = set;
  write.descriptorCount = 1;
  write.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  write.pImageInfo = &image_info;
  vkUpdateDescriptorSets(context_.device(), 1, &write, 0, nullptr);
  textures_.push_back(std::move(image));
  texture_sets_.push_back(set);
}

}  // namespace aar
