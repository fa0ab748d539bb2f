#include "aar/renderer/shadow_map.h"

#include <cstring>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <string>

#include "aar/error.h"
#include "aar/renderer/sun_camera.h"

namespace aar {
namespace {

constexpr uint32_t kMaxSlots = 64;  // instants of one exposure

// scene.frag's ShadowUniforms, member for member (std140: four 16-byte columns, then vec4s).
struct ShadowUniforms {
  glm::mat4 sun_camera_from_tanker;
  glm::vec4 sun_intrinsics;
  glm::vec4 camera_centre_in_tanker;
  glm::vec4 map;
};

}  // namespace

nlohmann::json ShadowsJson(int width, int height) {
  return {{"method",
           "shadow map: per instant a pinhole sun camera sun_camera_distance_m towards the sun frames the receiver "
           "and its propellers and renders the depth of every model along its axis (one sample per texel); a "
           "surface point takes the sun's light, diffuse and specular, times the bilinear share of the four texels "
           "around its projection that are not nearer the sun than the point less bias_m + slope_bias_texels "
           "texels x tan(angle to the sun)"},
          {"map_texels", {width, height}},
          {"sun_camera_distance_m", kSunCameraDistanceM},
          {"bias_m", kShadowBiasM},
          {"slope_bias_texels", kShadowSlopeBiasTexels},
          {"casters", "every model"},
          {"shadowed", "the receiver and its propellers (elsewhere the sun shines unshadowed)"}};
}

ShadowMaps::ShadowMaps(VulkanContext& context, int width, int height)
    : context_(context), width_(width), height_(height) {
  VkDevice device = context_.device();
  VkDescriptorSetLayoutBinding bindings[2]{};
  bindings[0].binding = 0;
  bindings[0].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  bindings[0].descriptorCount = 1;
  bindings[0].stageFlags = VK_SHADER_STAGE_FRAGMENT_BIT;
  bindings[1].binding = 1;
  bindings[1].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
  bindings[1].descriptorCount = 1;
  bindings[1].stageFlags = VK_SHADER_STAGE_FRAGMENT_BIT;
  VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  set_info.bindingCount = 2;
  set_info.pBindings = bindings;
  VkCheck(vkCreateDescriptorSetLayout(device, &set_info, nullptr, &layout_), "vkCreateDescriptorSetLayout(shadows)");

  const VkDescriptorPoolSize sizes[2] = {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, kMaxSlots},
                                         {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, kMaxSlots}};
  VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool_info.maxSets = kMaxSlots;
  pool_info.poolSizeCount = 2;
  pool_info.pPoolSizes = sizes;
  VkCheck(vkCreateDescriptorPool(device, &pool_info, nullptr, &pool_), "vkCreateDescriptorPool(shadows)");

  // Read with texelFetch: nearest, no mips.
  VkSamplerCreateInfo sampler{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  sampler.magFilter = sampler.minFilter = VK_FILTER_NEAREST;
  sampler.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  sampler.addressModeU = sampler.addressModeV = sampler.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  VkCheck(vkCreateSampler(device, &sampler, nullptr, &sampler_), "vkCreateSampler(shadows)");
}

ShadowMaps::~ShadowMaps() {
  VkDevice device = context_.device();
  vkDeviceWaitIdle(device);
  slots_.clear();
  if (sampler_) vkDestroySampler(device, sampler_, nullptr);
  if (pool_) vkDestroyDescriptorPool(device, pool_, nullptr);
  if (layout_) vkDestroyDescriptorSetLayout(device, layout_, nullptr);
}

ShadowMaps::Slot& ShadowMaps::SlotAt(size_t slot) {
  if (slot >= kMaxSlots) throw Error("shadows: at most " + std::to_string(kMaxSlots) + " instants per exposure");
  while (slots_.size() <= slot) {
    Slot s;
    GpuImageDesc desc;
    desc.width = static_cast<uint32_t>(width_);
    desc.height = static_cast<uint32_t>(height_);
    desc.format = VK_FORMAT_R32_SFLOAT;
    desc.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    s.depth = GpuImage(context_, desc);
    s.staging = GpuBuffer(context_, static_cast<VkDeviceSize>(width_) * height_ * sizeof(float),
                          VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
    s.uniforms = GpuBuffer(context_, sizeof(ShadowUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true);
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = pool_;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &layout_;
    VkCheck(vkAllocateDescriptorSets(context_.device(), &alloc, &s.set), "vkAllocateDescriptorSets(shadows)");
    const VkDescriptorImageInfo image_info{sampler_, s.depth.view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    const VkDescriptorBufferInfo buffer_info{s.uniforms.buffer(), 0, sizeof(ShadowUniforms)};
    VkWriteDescriptorSet writes[2]{{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}, {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}};
    writes[0].dstSet = writes[1].dstSet = s.set;
    writes[0].dstBinding = 0;
    writes[0].descriptorCount = 1;
    writes[0].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    writes[0].pImageInfo = &image_info;
    writes[1].dstBinding = 1;
    writes[1].descriptorCount = 1;
    writes[1].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    writes[1].pBufferInfo = &buffer_info;
    vkUpdateDescriptorSets(context_.device(), 2, writes, 0, nullptr);
    slots_.push_back(std::move(s));
  }
  return slots_[slot];
}

void ShadowMaps::Upload(size_t slot, const GroundTruthImage& sun_view, const Camera& sun_camera) {
  if (sun_view.width != width_ || sun_view.height != height_) {
    throw Error("shadows: the sun's view is " + std::to_string(sun_view.width) + "x" + std::to_string(sun_view.height) +
                ", the maps " + std::to_string(width_) + "x" + std::to_string(height_));
  }
  Slot& s = SlotAt(slot);
  std::memcpy(s.staging.mapped(), sun_view.depth_m.data(), sun_view.depth_m.size() * sizeof(float));
  context_.SubmitAndWait([&](VkCommandBuffer cmd) {
    TransitionImage(cmd, s.depth.image(), VK_IMAGE_ASPECT_COLOR_BIT, 1, VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {static_cast<uint32_t>(width_), static_cast<uint32_t>(height_), 1};
    vkCmdCopyBufferToImage(cmd, s.staging.buffer(), s.depth.image(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
    TransitionImage(cmd, s.depth.image(), VK_IMAGE_ASPECT_COLOR_BIT, 1, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  });
  s.sun_camera = sun_camera;
}

VkDescriptorSet ShadowMaps::Bind(size_t slot, const Eigen::Vector3d& camera_centre_in_tanker) {
  Slot& s = SlotAt(slot);
  ShadowUniforms u{};
  const Eigen::Matrix4f sun_camera_from_tanker = s.sun_camera.tanker_from_camera.inverse().matrix().cast<float>();
  u.sun_camera_from_tanker = glm::make_mat4(sun_camera_from_tanker.data());
  const Intrinsics& k = s.sun_camera.intrinsics;
  u.sun_intrinsics = glm::vec4(static_cast<float>(k.fx_px), static_cast<float>(k.fy_px), static_cast<float>(k.cx_px),
                               static_cast<float>(k.cy_px));
  const Eigen::Vector3f c = camera_centre_in_tanker.cast<float>();
  u.camera_centre_in_tanker = glm::vec4(c.x(), c.y(), c.z(), 0.0f);
  u.map = glm::vec4(static_cast<float>(width_), static_cast<float>(height_), kShadowBiasM, kShadowSlopeBiasTexels);
  std::memcpy(s.uniforms.mapped(), &u, sizeof(u));
  return s.set;
}

}  // namespace aar
