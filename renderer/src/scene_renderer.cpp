#include "aar/renderer/scene_renderer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <optional>

#include "aar/error.h"
#include "aar/progress.h"
#include "aar/renderer/background_texture.h"
#include "aar/renderer/pipeline_builder.h"
#include "aar/renderer/projection.h"
#include "aar/renderer/render_target.h"
#include "spirv/background_frag.h"
#include "spirv/background_truth_frag.h"
#include "spirv/background_vert.h"
#include "spirv/depth_frag.h"
#include "spirv/scene_frag.h"
#include "spirv/scene_pbr_frag.h"
#include "spirv/scene_pbr_shadow_frag.h"
#include "spirv/scene_shadow_frag.h"
#include "spirv/scene_vert.h"

namespace aar {
namespace {

constexpr VkFormat kColorFormat = VK_FORMAT_R16G16B16A16_SFLOAT;  // linear colour, averaged by the resolve
constexpr VkFormat kTruthFormat = VK_FORMAT_R32G32_SFLOAT;        // depth [m], object id

// The push-constant block of shaders/scene.vert, scene.frag and depth.frag,
// member for member (std430 offsets 0, 64, 112; no padding).
struct PushConstants {
  glm::mat4 clip_from_object;            // column-major, as Eigen's
  glm::vec4 tanker_from_object_rows[3];  // rotation rows (xyz); w: metallic, roughness (Shading::kPbr; else 0),
                                         // emissive 1 or 0
  glm::vec4 base_color_factor;           // linear RGBA; .a carries the object id in the ground-truth pass
};
static_assert(offsetof(PushConstants, tanker_from_object_rows) == 64 &&
                  offsetof(PushConstants, base_color_factor) == 112,
              "push constants must match the GLSL block's layout");
static_assert(sizeof(PushConstants) == 128, "push constants must fit the guaranteed 128 bytes");

}  // namespace

struct SceneRenderer::GpuModel {
  struct Draw {
    uint32_t first_index = 0;
    uint32_t index_count = 0;
    int32_t vertex_offset = 0;
    int texture_set = 0;
    std::array<float, 4> base_color_factor{};
    float metallic = 0.0f, roughness = 0.0f;
    bool emissive = false;
  };
  GpuBuffer vertices;
  GpuBuffer indices;
  std::vector<Draw> draws;
  MeshGeometry geometry;  // object frame, for the render-area rectangle
};

struct SceneRenderer::Target {
  Target(VulkanContext& context, uint32_t width, uint32_t height, int samples, VkFormat color_format)
      : frame(context, width, height, samples, color_format), device(context.device()) {}
  ~Target() {
    if (pipeline) vkDestroyPipeline(device, pipeline, nullptr);
    if (background_pipeline) vkDestroyPipeline(device, background_pipeline, nullptr);
  }
  Target(const Target&) = delete;
  Target& operator=(const Target&) = delete;

  RenderTarget frame;
  VkDevice device = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkPipeline background_pipeline = VK_NULL_HANDLE;  // single-sample targets, with a background
  std::array<float, 3> sky{};                       // flat sky: a resolved sky pixel as this target produces it
};

SceneRenderer::SceneRenderer(VulkanContext& context, int width, int height, const SceneRendererOptions& options)
    : context_(context), width_(width), height_(height), options_(options) {
  VkDevice device = context_.device();
  VkDescriptorSetLayoutBinding binding{};
  binding.binding = 0;
  binding.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  binding.descriptorCount = 1;
  binding.stageFlags = VK_SHADER_STAGE_FRAGMENT_BIT;
  VkDescriptorSetLayoutCreateInfo set_info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  set_info.bindingCount = 1;
  set_info.pBindings = &binding;
  VkCheck(vkCreateDescriptorSetLayout(device, &set_info, nullptr, &set_layout_), "vkCreateDescriptorSetLayout");

  // With shadows, set 1 holds the sun's depth map (shadow_map.h).
  if (options_.shadows) shadows_ = std::make_unique<ShadowMaps>(context_, width_, height_);
  const VkDescriptorSetLayout set_layouts[2] = {set_layout_, shadows_ ? shadows_->layout() : VK_NULL_HANDLE};
  VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(PushConstants)};
  VkPipelineLayoutCreateInfo layout_info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  layout_info.setLayoutCount = shadows_ ? 2 : 1;
  layout_info.pSetLayouts = set_layouts;
  layout_info.pushConstantRangeCount = 1;
  layout_info.pPushConstantRanges = &range;
  VkCheck(vkCreatePipelineLayout(device, &layout_info, nullptr, &pipeline_layout_), "vkCreatePipelineLayout");

  VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, kMaxTextures};
  VkDescriptorPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  pool_info.maxSets = kMaxTextures;
  pool_info.poolSizeCount = 1;
  pool_info.pPoolSizes = &pool_size;
  VkCheck(vkCreateDescriptorPool(device, &pool_info, nullptr, &descriptor_pool_), "vkCreateDescriptorPool");

  VkSamplerCreateInfo sampler{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  sampler.magFilter = VK_FILTER_LINEAR;
  sampler.minFilter = VK_FILTER_LINEAR;
  sampler.mipmapMode = VK_SAMPLER_MIPMAP_MODE_LINEAR;
  sampler.addressModeU = sampler.addressModeV = sampler.addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT;
  const float anisotropy = std::min(options_.max_anisotropy, context_.info().max_anisotropy);
  sampler.anisotropyEnable = anisotropy > 1.0f ? VK_TRUE : VK_FALSE;
  sampler.maxAnisotropy = anisotropy;
  sampler.maxLod = VK_LOD_CLAMP_NONE;
  VkCheck(vkCreateSampler(device, &sampler, nullptr, &sampler_), "vkCreateSampler");

  vert_ = CreateShaderModule(device, kSpirv_scene_vert, sizeof(kSpirv_scene_vert));
  const bool pbr = options_.shading == Shading::kPbr;
  if (options_.shadows) {
    frag_ = pbr ? CreateShaderModule(device, kSpirv_scene_pbr_shadow_frag, sizeof(kSpirv_scene_pbr_shadow_frag))
                : CreateShaderModule(device, kSpirv_scene_shadow_frag, sizeof(kSpirv_scene_shadow_frag));
  } else {
    frag_ = pbr ? CreateShaderModule(device, kSpirv_scene_pbr_frag, sizeof(kSpirv_scene_pbr_frag))
                : CreateShaderModule(device, kSpirv_scene_frag, sizeof(kSpirv_scene_frag));
  }
  depth_frag_ = CreateShaderModule(device, kSpirv_depth_frag, sizeof(kSpirv_depth_frag));

  readback_ = GpuBuffer(context_, static_cast<VkDeviceSize>(width_) * height_ * 8, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                        /*host_visible=*/true);

  // Texture set 0: 1x1 white, for primitives without a base colour texture.
  UploadTexture(BuildMips({255, 255, 255, 255}, 1, 1));

  const BackgroundOptions& bg = options_.background;
  bg.Check();
  sun_direction_in_tanker_ = LevelFromTanker(bg).transpose() * SunInLevel(bg);
  std::optional<TextureMips> surface;
  if (bg.enabled()) {
    background_vert_ = CreateShaderModule(device, kSpirv_background_vert, sizeof(kSpirv_background_vert));
    background_frag_ = CreateShaderModule(device, kSpirv_background_frag, sizeof(kSpirv_background_frag));
    background_truth_frag_ =
        CreateShaderModule(device, kSpirv_background_truth_frag, sizeof(kSpirv_background_truth_frag));
    if (bg.kind == BackgroundKind::kTerrain || bg.kind == BackgroundKind::kClouds) {
      background_texture_set_ = static_cast<int>(texture_sets_.size());
      surface = bg.kind == BackgroundKind::kTerrain ? TerrainTexture(bg.seed) : CloudTexture(bg.seed);
      UploadTexture(*surface);
    }
  }
  SetLightConstants(surface ? &*surface : nullptr);
}

SceneRenderer::~SceneRenderer() {
  VkDevice device = context_.device();
  vkDeviceWaitIdle(device);
  targets_.clear();
  shadows_.reset();
  for (VkShaderModule m : {vert_, frag_, depth_frag_, background_vert_, background_frag_, background_truth_frag_}) {
    if (m) vkDestroyShaderModule(device, m, nullptr);
  }
  if (sampler_) vkDestroySampler(device, sampler_, nullptr);
  if (descriptor_pool_) vkDestroyDescriptorPool(device, descriptor_pool_, nullptr);
  if (pipeline_layout_) vkDestroyPipelineLayout(device, pipeline_layout_, nullptr);
  if (set_layout_) vkDestroyDescriptorSetLayout(device, set_layout_, nullptr);
}

int SceneRenderer::AddModel(const SceneModel& model) {
  // Textures: staging buffer -> optimal-tiling sRGB image with the CPU-built mip chain.
  const int first_set = static_cast<int>(texture_sets_.size());
  for (const TextureMips& mips : model.textures) UploadTexture(mips);

  // Geometry: one vertex and one index buffer per model.
  auto gpu = std::make_unique<GpuModel>();
  size_t vertex_count = 0, index_count = 0;
  for (const Primitive& p : model.primitives) {
    vertex_count += p.vertices.size();
    index_count += p.indices.size();
  }
  if (vertex_count > 0) {
    gpu->vertices = GpuBuffer(context_, vertex_count * sizeof(Vertex), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, true);
    gpu->indices = GpuBuffer(context_, index_count * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT, true);
    size_t v = 0, i = 0;
    for (const Primitive& p : model.primitives) {
      std::memcpy(static_cast<Vertex*>(gpu->vertices.mapped()) + v, p.vertices.data(),
                  p.vertices.size() * sizeof(Vertex));
      std::memcpy(static_cast<uint32_t*>(gpu->indices.mapped()) + i, p.indices.data(),
                  p.indices.size() * sizeof(uint32_t));
      GpuModel::Draw draw;
      draw.first_index = static_cast<uint32_t>(i);
      draw.index_count = static_cast<uint32_t>(p.indices.size());
      draw.vertex_offset = static_cast<int32_t>(v);
      draw.texture_set = p.texture >= 0 ? first_set + p.texture : 0;
      draw.base_color_factor = p.base_color_factor;
      draw.metallic = p.metallic;
      draw.roughness = p.roughness;
      draw.emissive = p.emissive;
      gpu->draws.push_back(draw);
      v += p.vertices.size();
      i += p.indices.size();
    }
  }
  gpu->geometry = MeshGeometryOf(model);
  models_.push_back(std::move(gpu));
  return static_cast<int>(models_.size()) - 1;
}

const MeshGeometry& SceneRenderer::GeometryOf(int model) const { return models_.at(model)->geometry; }

SceneRenderer::Target& SceneRenderer::TargetFor(int samples, bool ground_truth) {
  auto& slot = targets_[{samples, ground_truth}];
  if (slot) return *slot;
  const uint32_t w = static_cast<uint32_t>(width_), h = static_cast<uint32_t>(height_);
  auto t = std::make_unique<Target>(context_, w, h, samples, ground_truth ? kTruthFormat : kColorFormat);
  PipelineBuilder builder;
  builder.vertex_shader = vert_;
  builder.fragment_shader = ground_truth ? depth_frag_ : frag_;
  builder.layout = pipeline_layout_;
  builder.samples = static_cast<VkSampleCountFlagBits>(samples);
  builder.width = w;
  builder.height = h;
  if (!ground_truth) builder.fragment_specialization = scene_constants_.Info();
  t->pipeline = builder.Build(t->device, t->frame.render_pass());
  if (options_.background.enabled() && samples == 1) {
    PipelineBuilder background = builder;
    background.vertex_shader = background_vert_;
    background.fragment_shader = ground_truth ? background_truth_frag_ : background_frag_;
    background.scene_geometry = false;
    background.fragment_specialization =
        ground_truth || background_constants_.empty() ? nullptr : background_constants_.Info();
    t->background_pipeline = background.Build(t->device, t->frame.render_pass());
  }
  slot = std::move(t);
  if (!ground_truth && !options_.background.enabled()) {
    // Sky pixels outside the render area are filled with this value, read
    // back from a 1x1 render of nothing, so they equal rendered sky exactly.
    const PixelRect corner{0, 0, 1, 1};
    context_.SubmitAndWait(
        [&](VkCommandBuffer cmd) { Record(cmd, *slot, Eigen::Matrix4d::Identity(), {}, false, corner, nullptr); });
    ReadBack(*slot, corner);
    const auto* half = static_cast<const Eigen::half*>(readback_.mapped());
    for (int c = 0; c < 3; ++c) slot->sky[c] = static_cast<float>(half[c]);
  }
  return *slot;
}

void SceneRenderer::Record(VkCommandBuffer cmd, Target& target, const Eigen::Matrix4d& clip_from_tanker,
                           const std::vector<RenderItem>& items, bool ground_truth, const PixelRect& area,
                           const BackgroundPush* background, VkDescriptorSet shadow_set) {
  VkClearValue clears[2]{};
  if (ground_truth || options_.background.enabled()) {
    // Truth: no surface. Colour over a background: transparent, so that the
    // resolved alpha is the aircraft's coverage (RenderColor composites).
    clears[0].color = {{0.0f, 0.0f, 0.0f, 0.0f}};
  } else {
    clears[0].color = {{options_.sky_linear[0], options_.sky_linear[1], options_.sky_linear[2], 1.0f}};
  }
  clears[1].depthStencil = {0.0f, 0};  // reversed depth: 0 is infinitely far
  VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  begin.renderPass = target.frame.render_pass();
  begin.framebuffer = target.frame.framebuffer();
  begin.renderArea = {{area.x0, area.y0}, {static_cast<uint32_t>(area.width()), static_cast<uint32_t>(area.height())}};
  begin.clearValueCount = 2;
  begin.pClearValues = clears;
  vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
  vkCmdSetScissor(cmd, 0, 1, &begin.renderArea);
  if (background) {
    // Behind everything: no depth test or write, the aircraft draw over it.
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, target.background_pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_layout_, 0, 1,
                            &texture_sets_[background_texture_set_], 0, nullptr);
    vkCmdPushConstants(cmd, pipeline_layout_, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                       sizeof(BackgroundPush), background);
    vkCmdDraw(cmd, 3, 1, 0, 0);
  }
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, target.pipeline);
  if (shadow_set != VK_NULL_HANDLE) {
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_layout_, 1, 1, &shadow_set, 0, nullptr);
  }
  for (const RenderItem& item : items) {
    if (item.model < 0 || item.model >= static_cast<int>(models_.size())) throw Error("render item: bad model index");
    const GpuModel& model = *models_[item.model];
    if (model.draws.empty()) continue;
    PushConstants pc{};
    const Eigen::Matrix4f clip_from_object = (clip_from_tanker * item.tanker_from_object.matrix()).cast<float>();
    pc.clip_from_object = glm::make_mat4(clip_from_object.data());
    // Row 2 is (0, 0, 0, near) (projection.h); scene.vert reads the object's
    // place in the tanker frame from its first three entries.
    for (int col = 0; col < 3; ++col)
      pc.clip_from_object[col][2] = static_cast<float>(item.tanker_from_object.translation()[col]);
    const Eigen::Matrix3f r = item.tanker_from_object.linear().cast<float>();
    for (int row = 0; row < 3; ++row)
      pc.tanker_from_object_rows[row] = glm::vec4(r(row, 0), r(row, 1), r(row, 2), 0.0f);
    const VkDeviceSize zero = 0;
    VkBuffer vertex_buffer = model.vertices.buffer();
    vkCmdBindVertexBuffers(cmd, 0, 1, &vertex_buffer, &zero);
    vkCmdBindIndexBuffer(cmd, model.indices.buffer(), 0, VK_INDEX_TYPE_UINT32);
    for (const GpuModel::Draw& draw : model.draws) {
      pc.base_color_factor = glm::make_vec4(draw.base_color_factor.data());
      if (ground_truth) pc.base_color_factor.a = item.object_id;
      if (options_.shading == Shading::kPbr && !ground_truth) {
        pc.tanker_from_object_rows[0].w = draw.metallic;
        pc.tanker_from_object_rows[1].w = draw.roughness;
      }
      if (!ground_truth) pc.tanker_from_object_rows[2].w = draw.emissive ? 1.0f : 0.0f;
      vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_layout_, 0, 1,
                              &texture_sets_[draw.texture_set], 0, nullptr);
      vkCmdPushConstants(cmd, pipeline_layout_, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                         sizeof(PushConstants), &pc);
      vkCmdDrawIndexed(cmd, draw.index_count, 1, draw.first_index, draw.vertex_offset, 0);
    }
  }
  vkCmdEndRenderPass(cmd);
}

void SceneRenderer::ReadBack(const Target& target, const PixelRect& area) {
  context_.SubmitAndWait([&](VkCommandBuffer cmd) {
    VkBufferImageCopy copy{};
    copy.bufferRowLength = static_cast<uint32_t>(area.width());
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageOffset = {area.x0, area.y0, 0};
    copy.imageExtent = {static_cast<uint32_t>(area.width()), static_cast<uint32_t>(area.height()), 1};
    vkCmdCopyImageToBuffer(cmd, target.frame.Output().image(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback_.buffer(),
                           1, &copy);
    VkMemoryBarrier barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &barrier, 0, nullptr, 0,
                         nullptr);
  });
}

SceneRenderer::ViewArea SceneRenderer::RenderArea(const Eigen::Matrix4d& clip_from_tanker,
                                                  const std::vector<RenderItem>& items) const {
  if (options_.full_frame) return {PixelRect{0, 0, width_, height_}, items};
  // Jitter moves the image by less than a pixel; 3 px of margin covers it and the rasterizer's rounding.
  constexpr int kMarginPx = 3;
  ViewArea area{PixelRect{width_, height_, 0, 0}, {}};
  for (const RenderItem& item : items) {
    const GpuModel& model = *models_.at(item.model);
    const PixelRect r =
        GeometryRect(clip_from_tanker * item.tanker_from_object.matrix(), model.geometry, width_, height_, kMarginPx);
    if (r.empty()) continue;  // no part within the margin of the image: drawing it would change no pixel
    area.items.push_back(item);
    const PixelRect& a = area.rect;
    area.rect = {std::min(a.x0, r.x0), std::min(a.y0, r.y0), std::max(a.x1, r.x1), std::max(a.y1, r.y1)};
  }
  if (area.rect.empty()) area.rect = {0, 0, 1, 1};  // nothing in view: render one sky pixel
  return area;
}

LinearImage SceneRenderer::RenderColor(const Camera& camera, double near_m, const std::vector<RenderItem>& items,
                                       const MsaaPlan& plan, ViewTimings* timings) {
  return RenderExposure(camera, near_m, {items}, plan, timings);
}

LinearImage SceneRenderer::RenderExposure(const Camera& camera, double near_m,
                                          const std::vector<std::vector<RenderItem>>& items_at_times,
                                          const MsaaPlan& plan, ViewTimings* timings, const PixelRect* rows) {
  const size_t instants = items_at_times.size(), jitters = plan.offsets_px.size();
  const size_t passes = std::max(instants, jitters);
  if (instants == 0 || passes % instants != 0 || passes % jitters != 0) {
    throw Error("exposure: " + std::to_string(instants) + " instants and " + std::to_string(jitters) +
                " MSAA passes: the larger must be a multiple of the smaller");
  }
  Target& target = TargetFor(plan.native_samples, false);
  LinearImage out;
  out.width = width_;
  out.height = height_;
  out.rgb.resize(static_cast<size_t>(width_) * height_ * 3);
  const bool background = options_.background.enabled();
  if (background) {
    out.rgb = BackgroundOf(camera, timings);
  } else {
    for (size_t i = 0; i < out.rgb.size(); ++i) out.rgb[i] = target.sky[i % 3];
  }
  // Only the rectangle that can hold geometry is rendered with MSAA, and only
  // the objects that reach into it are drawn; the rest is sky or background.
  // (over an exposure: the union of the instants' rectangles).
  const Eigen::Matrix4d cam_from_tanker = camera.tanker_from_camera.inverse().matrix();
  std::vector<ViewArea> views;
  for (const std::vector<RenderItem>& items : items_at_times)
    views.push_back(RenderArea(ClipFromCamera(camera.intrinsics, near_m) * cam_from_tanker, items));
  PixelRect area = views.front().rect;
  for (const ViewArea& v : views) {
    area = {std::min(area.x0, v.rect.x0), std::min(area.y0, v.rect.y0), std::max(area.x1, v.rect.x1),
            std::max(area.y1, v.rect.y1)};
  }
  if (rows) {
    area.y0 = std::max(area.y0, rows->y0);
    area.y1 = std::min(area.y1, rows->y1);
    if (area.empty()) return out;  // no geometry in these rows: background alone
  }
  if (shadows_) {
    const auto start = std::chrono::steady_clock::now();
    for (size_t t = 0; t < instants; ++t) PrepareShadowMap(t, items_at_times[t]);
    if (timings) timings->render_ms += MillisecondsSince(start);
  }
  std::vector<float> sum(static_cast<size_t>(area.width()) * area.height() * 4, 0.0f);  // linear RGBA
  const float weight = 1.0f / static_cast<float>(passes);
  for (size_t pass = 0; pass < passes; ++pass) {
    auto start = std::chrono::steady_clock::now();
    const Vec2& jitter = plan.offsets_px[pass % jitters];
    const std::vector<RenderItem>& items = views[pass % instants].items;
    const Eigen::Matrix4d clip_from_tanker =
        ClipFromCamera(camera.intrinsics, near_m, jitter.x, jitter.y) * cam_from_tanker;
    const VkDescriptorSet shadow =
        shadows_ ? shadows_->Bind(pass % instants, camera.tanker_from_camera.translation()) : VK_NULL_HANDLE;
    context_.SubmitAndWait(
        [&](VkCommandBuffer cmd) { Record(cmd, target, clip_from_tanker, items, false, area, nullptr, shadow); });
    if (timings) timings->render_ms += MillisecondsSince(start);
    start = std::chrono::steady_clock::now();
    ReadBack(target, area);
    const auto* half = static_cast<const Eigen::half*>(readback_.mapped());
    for (size_t i = 0; i < sum.size(); ++i) sum[i] += weight * static_cast<float>(half[i]);
    if (timings) timings->readback_ms += MillisecondsSince(start);
  }
  // Over a background the passes were cleared transparent: alpha is the
  // aircraft's coverage of the pixel's samples, and the colour is
  // premultiplied by it, so the uncovered rest shows the background (exactly
  // the background where nothing covers the pixel, exactly the aircraft where
  // it covers every sample). Over the flat sky the passes drew the sky.
  for (int y = 0; y < area.height(); ++y) {
    const float* in = &sum[static_cast<size_t>(y) * area.width() * 4];
    float* row = &out.rgb[(static_cast<size_t>(y + area.y0) * width_ + area.x0) * 3];
    for (int x = 0; x < area.width(); ++x) {
      const float uncovered = 1.0f - in[x * 4 + 3];
      for (int c = 0; c < 3; ++c)
        row[x * 3 + c] = background ? in[x * 4 + c] + uncovered * row[x * 3 + c] : in[x * 4 + c];
    }
  }
  return out;
}

GroundTruthImage SceneRenderer::RenderGroundTruth(const Camera& camera, double near_m,
                                                  const std::vector<RenderItem>& items, const PixelRect* rows) {
  return TruthPass(camera, near_m, items, rows, options_.background.enabled());
}

GroundTruthImage SceneRenderer::TruthPass(const Camera& camera, double near_m, const std::vector<RenderItem>& items,
                                          const PixelRect* rows, bool with_background) {
  GroundTruthImage out;
  out.width = width_;
  out.height = height_;
  const size_t pixels = static_cast<size_t>(width_) * height_;
  out.depth_m.assign(pixels, 0.0f);
  out.object_id.assign(pixels, 0);
  const PixelRect area = rows ? PixelRect{0, std::max(rows->y0, 0), width_, std::min(rows->y1, height_)}
                              : PixelRect{0, 0, width_, height_};
  if (area.empty()) return out;
  Target& target = TargetFor(1, true);
  const Eigen::Matrix4d clip_from_tanker =
      ClipFromCamera(camera.intrinsics, near_m) * camera.tanker_from_camera.inverse().matrix();
  std::optional<BackgroundPush> background;
  if (with_background) background = BackgroundFor(camera);
  context_.SubmitAndWait([&](VkCommandBuffer cmd) {
    Record(cmd, target, clip_from_tanker, items, true, area, background ? &*background : nullptr);
  });
  ReadBack(target, area);
  const float* data = static_cast<const float*>(readback_.mapped());
  const size_t first = static_cast<size_t>(area.y0) * width_, count = static_cast<size_t>(area.height()) * width_;
  for (size_t i = 0; i < count; ++i) {
    out.depth_m[first + i] = data[i * 2];
    out.object_id[first + i] = static_cast<uint8_t>(std::lround(data[i * 2 + 1]));
  }
  return out;
}

}  // namespace aar
