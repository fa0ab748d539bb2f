#include "aar/renderer/render_target.h"

#include <vector>

namespace aar {
namespace {

// Colour, depth and, when multisampled, resolve attachments, in that order.
std::vector<VkAttachmentDescription> AttachmentDescriptions(VkFormat color_format, int samples) {
  const auto sample_bits = static_cast<VkSampleCountFlagBits>(samples);
  std::vector<VkAttachmentDescription> attachments(samples > 1 ? 3 : 2);
  attachments[0] = {0,
                    color_format,
                    sample_bits,
                    VK_ATTACHMENT_LOAD_OP_CLEAR,
                    samples > 1 ? VK_ATTACHMENT_STORE_OP_DONT_CARE : VK_ATTACHMENT_STORE_OP_STORE,
                    VK_ATTACHMENT_LOAD_OP_DONT_CARE,
                    VK_ATTACHMENT_STORE_OP_DONT_CARE,
                    VK_IMAGE_LAYOUT_UNDEFINED,
                    samples > 1 ? VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL};
  attachments[1] = {0,
                    kDepthFormat,
                    sample_bits,
                    VK_ATTACHMENT_LOAD_OP_CLEAR,
                    VK_ATTACHMENT_STORE_OP_DONT_CARE,
                    VK_ATTACHMENT_LOAD_OP_DONT_CARE,
                    VK_ATTACHMENT_STORE_OP_DONT_CARE,
                    VK_IMAGE_LAYOUT_UNDEFINED,
                    VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  if (samples > 1) {
    attachments[2] = {0,
                      color_format,
                      VK_SAMPLE_COUNT_1_BIT,
                      VK_ATTACHMENT_LOAD_OP_DONT_CARE,
                      VK_ATTACHMENT_STORE_OP_STORE,
                      VK_ATTACHMENT_LOAD_OP_DONT_CARE,
                      VK_ATTACHMENT_STORE_OP_DONT_CARE,
                      VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL};
  }
  return attachments;
}

// One subpass drawing into the attachments, its colour output then read by a transfer.
VkRenderPass CreateRenderPass(VkDevice device, VkFormat color_format, int samples) {
  const std::vector<VkAttachmentDescription> attachments = AttachmentDescriptions(color_format, samples);
  VkAttachmentReference color_ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkAttachmentReference depth_ref{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkAttachmentReference resolve_ref{2, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = 1;
  subpass.pColorAttachments = &color_ref;
  subpass.pDepthStencilAttachment = &depth_ref;
  subpass.pResolveAttachments = samples > 1 ? &resolve_ref : nullptr;
  VkSubpassDependency dependency{};
  dependency.srcSubpass = 0;
  dependency.dstSubpass = VK_SUBPASS_EXTERNAL;
  dependency.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
  dependency.dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
  dependency.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
  dependency.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
  VkRenderPassCreateInfo rp{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  rp.attachmentCount = static_cast<uint32_t>(attachments.size());
  rp.pAttachments = attachments.data();
  rp.subpassCount = 1;
  rp.pSubpasses = &subpass;
  rp.dependencyCount = 1;
  rp.pDependencies = &dependency;
  VkRenderPass render_pass = VK_NULL_HANDLE;
  VkCheck(vkCreateRenderPass(device, &rp, nullptr, &render_pass), "vkCreateRenderPass");
  return render_pass;
}

}  // namespace

RenderTarget::RenderTarget(VulkanContext& context, uint32_t w, uint32_t h, int samples, VkFormat color_format)
    : device_(context.device()), samples_(samples) {
  const auto sample_bits = static_cast<VkSampleCountFlagBits>(samples);
  GpuImageDesc color{w,
                     h,
                     1,
                     color_format,
                     sample_bits,
                     static_cast<VkImageUsageFlags>(VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT |
                                                    (samples == 1 ? VK_IMAGE_USAGE_TRANSFER_SRC_BIT : 0)),
                     VK_IMAGE_ASPECT_COLOR_BIT};
  color_ = GpuImage(context, color);
  depth_ = GpuImage(context, {w, h, 1, kDepthFormat, sample_bits, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                              VK_IMAGE_ASPECT_DEPTH_BIT});
  if (samples > 1) {
    resolve_ = GpuImage(
        context, {w, h, 1, color_format, VK_SAMPLE_COUNT_1_BIT,
                  VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT, VK_IMAGE_ASPECT_COLOR_BIT});
  }

  render_pass_ = CreateRenderPass(device_, color_format, samples);

  std::vector<VkImageView> views = {color_.view(), depth_.view()};
  if (samples > 1) views.push_back(resolve_.view());
  VkFramebufferCreateInfo fb{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  fb.renderPass = render_pass_;
  fb.attachmentCount = static_cast<uint32_t>(views.size());
  fb.pAttachments = views.data();
  fb.width = w;
  fb.height = h;
  fb.layers = 1;
  const VkResult result = vkCreateFramebuffer(device_, &fb, nullptr, &framebuffer_);
  if (result != VK_SUCCESS) vkDestroyRenderPass(device_, render_pass_, nullptr);  // the destructor will not run
  VkCheck(result, "vkCreateFramebuffer");
}

RenderTarget::~RenderTarget() {
  if (framebuffer_) vkDestroyFramebuffer(device_, framebuffer_, nullptr);
  if (render_pass_) vkDestroyRenderPass(device_, render_pass_, nullptr);
}

}  // namespace aar
