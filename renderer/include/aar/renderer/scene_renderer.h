#pragma once
// Renders views of uploaded models with a pinhole camera: colour with MSAA
// (native or composed from jittered passes, docs/rendering.md) in linear
// floating point, and a one-sample ground-truth pass (depth, object id).
// Vulkan objects here only record and submit; the maths lives in
// projection.h and msaa.h.

#include <Eigen/Geometry>
#include <glm/vec4.hpp>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "aar/image.h"
#include "aar/renderer/background.h"
#include "aar/renderer/floodlight.h"
#include "aar/renderer/geometry_rect.h"
#include "aar/renderer/gpu_resources.h"
#include "aar/renderer/msaa.h"
#include "aar/renderer/pipeline_builder.h"
#include "aar/renderer/projection.h"
#include "aar/renderer/scene_model.h"
#include "aar/renderer/shading.h"
#include "aar/renderer/shadow_map.h"
#include "aar/renderer/vulkan_context.h"
#include "aar/rig.h"

namespace aar {

struct RenderItem {
  int model = 0;  ///< index returned by AddModel
  Eigen::Isometry3d tanker_from_object = Eigen::Isometry3d::Identity();
  float object_id = 0.0f;  ///< written by the ground-truth pass
};

struct ViewTimings {
  double render_ms = 0.0;    ///< recording, submission and GPU time of the passes
  double readback_ms = 0.0;  ///< copy to host memory, conversion and averaging
};

struct SceneRendererOptions {
  std::array<float, 3> sky_linear = {0.42f, 0.56f, 0.78f};  ///< background colour, linear RGB
  /// Texture anisotropic filtering cap (the device's limit applies too); 1 =
  /// trilinear only. Costly on lavapipe (x16 anisotropy is 2.5x slower).
  float max_anisotropy = 1.0f;
  /// What is behind the aircraft; the default (flat) is sky_linear everywhere.
  /// Otherwise one single-sample pass per camera draws it over the whole
  /// frame (once for all frames: it depends on the camera alone), the MSAA
  /// passes draw only the aircraft over a transparent clear, and their
  /// resolved coverage (alpha) composites the aircraft over it
  /// (docs/rendering.md, "Backgrounds").
  BackgroundOptions background;
  /// Render every pixel with MSAA, drawing every item, instead of only the
  /// rectangle that can hold geometry and the items that reach into it
  /// (geometry_rect.h); the same images, slower: the reference the rectangle
  /// is tested against.
  bool full_frame = false;
  Shading shading = Shading::kMatte;
  /// The sun's shadows (docs/rendering.md, "Shadows"): every item casts
  /// them, over the part of the scene the sun camera frames, the items with
  /// object id `shadow_object_id` (the receiver and its propellers).
  bool shadows = false;
  float shadow_object_id = 1.0f;
  /// The tanker's floodlight on the aircraft (floodlight.h), at the
  /// background's render scale (daylight.h); none: no floodlight.
  std::optional<Floodlight> floodlight;
};

class SceneRenderer {
 public:
  SceneRenderer(VulkanContext& context, int width, int height, const SceneRendererOptions& options = {});
  ~SceneRenderer();
  SceneRenderer(const SceneRenderer&) = delete;
  SceneRenderer& operator=(const SceneRenderer&) = delete;

  /// Uploads a model; returns its index for RenderItem::model.
  int AddModel(const SceneModel& model);

  LinearImage RenderColor(const Camera& camera, double near_m, const std::vector<RenderItem>& items,
                          const MsaaPlan& plan, ViewTimings* timings = nullptr);
  /// The same over an exposure (motion blur): `items_at_times` holds the
  /// scene at T evenly spaced instants of the exposure. The passes are
  /// max(plan.passes, T) (each a power of two; the larger must be a multiple
  /// of the smaller, else aar::Error): pass i draws the scene at instant
  /// i % T with the MSAA plan's jitter i % plan.passes, and all are averaged,
  /// so every instant and every jitter carries the same weight. One instant
  /// is RenderColor, pass for pass. With `rows`, only the image's rows
  /// [rows->y0, rows->y1) are rendered (a rolling shutter's band,
  /// rolling_shutter.h): elsewhere the image is background.
  LinearImage RenderExposure(const Camera& camera, double near_m,
                             const std::vector<std::vector<RenderItem>>& items_at_times, const MsaaPlan& plan,
                             ViewTimings* timings = nullptr, const PixelRect* rows = nullptr);
  /// Depth and object ids, one sample per pixel; with `rows`, of those rows
  /// only (elsewhere no surface, id 0).
  GroundTruthImage RenderGroundTruth(const Camera& camera, double near_m, const std::vector<RenderItem>& items,
                                     const PixelRect* rows = nullptr);

 private:
  struct Target;
  struct GpuModel;
  static constexpr uint32_t kMaxTextures = 64;
  void UploadTexture(const TextureMips& mips);  ///< scene_textures.cpp
  Target& TargetFor(int samples, bool ground_truth);
  /// An uploaded model's triangles and bounding box (object frame).
  const MeshGeometry& GeometryOf(int model) const;
  /// The push-constant block of shaders/background.frag, member for member.
  struct BackgroundPush {
    glm::vec4 level_from_pixel_rows[3];  // xyz: rows; w: camera level x, y [m], height above the ground [m]
    glm::vec4 sun_in_level;              // xyz; w: sea-level haze extinction [1/m]
    glm::vec4 surface;      // sin^2 dip, h (2R + h) / (R + h) [m], surface height [m], haze scale height [m]
    glm::vec4 texture_map;  // 1 / tile size [1/m], pixel angle [rad] (daylight), 0, kind (1 sky, 2 terrain, 3 clouds)
  };
  BackgroundPush BackgroundFor(const Camera& camera) const;
  /// The camera's background, linear RGB of the whole frame: rendered the
  /// first time, then the same pixels from the cache.
  const std::vector<float>& BackgroundOf(const Camera& camera, ViewTimings* timings);
  void Record(VkCommandBuffer cmd, Target& target, const Eigen::Matrix4d& clip_from_tanker,
              const std::vector<RenderItem>& items, bool ground_truth, const PixelRect& area,
              const BackgroundPush* background, VkDescriptorSet shadow_set = VK_NULL_HANDLE);
  /// RenderGroundTruth, over the background or not.
  GroundTruthImage TruthPass(const Camera& camera, double near_m, const std::vector<RenderItem>& items,
                             const PixelRect* rows, bool with_background);
  /// The sun's depth map of one instant's items into shadows_'s `slot`
  /// (scene_shadow_pass.cpp), unless the slot holds these items' already.
  void PrepareShadowMap(size_t slot, const std::vector<RenderItem>& items);
  void ReadBack(const Target& target, const PixelRect& area);
  /// The rectangle the MSAA passes render and the items that reach into it
  /// (all of them, over the whole frame, with options_.full_frame).
  struct ViewArea {
    PixelRect rect;
    std::vector<RenderItem> items;
  };
  ViewArea RenderArea(const Eigen::Matrix4d& clip_from_tanker, const std::vector<RenderItem>& items) const;

  VulkanContext& context_;
  int width_;
  int height_;
  SceneRendererOptions options_;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout pipeline_layout_ = VK_NULL_HANDLE;
  VkDescriptorPool descriptor_pool_ = VK_NULL_HANDLE;
  VkSampler sampler_ = VK_NULL_HANDLE;
  VkShaderModule vert_ = VK_NULL_HANDLE;
  VkShaderModule frag_ = VK_NULL_HANDLE;  // scene.frag, or scene_pbr_frag with Shading::kPbr
  VkShaderModule depth_frag_ = VK_NULL_HANDLE;
  VkShaderModule background_vert_ = VK_NULL_HANDLE;
  VkShaderModule background_frag_ = VK_NULL_HANDLE;
  VkShaderModule background_truth_frag_ = VK_NULL_HANDLE;
  /// scene.frag's and background.frag's specialization constants: the sun's
  /// direction, daylight's light and sky, the floodlight (scene_daylight.cpp).
  SpecializationConstants scene_constants_;
  SpecializationConstants background_constants_;
  /// Fills them; `surface` is the background's texture (none: the plain ground).
  void SetLightConstants(const TextureMips* surface);
  void SetDaylightConstants(const TextureMips* surface);
  Eigen::Vector3d sun_direction_in_tanker_ =
      Eigen::Vector3d::UnitZ();                   ///< the same in double (unit: a rotated unit vector)
  std::unique_ptr<ShadowMaps> shadows_;           ///< with options_.shadows
  std::vector<std::vector<double>> shadow_keys_;  ///< per slot: the items its map shows (model, id, pose)
  int background_texture_set_ = 0;                ///< the terrain or cloud texture (0: none)
  std::vector<std::unique_ptr<GpuModel>> models_;
  std::vector<GpuImage> textures_;
  std::vector<VkDescriptorSet> texture_sets_;  ///< one per texture; [0] is a 1x1 white texture
  std::map<std::pair<int, bool>, std::unique_ptr<Target>> targets_;
  GpuBuffer readback_;
  /// The background depends on the camera alone (its pose in the level
  /// frame, over which the tanker does not move; background.h), not on the
  /// frame: one pass per camera serves every frame. The last two cameras'
  /// (a stereo rig's), keyed by their background.frag push constants.
  struct CachedBackground {
    std::string push;
    std::vector<float> rgb;
  };
  static constexpr size_t kCachedBackgrounds = 2;
  std::vector<CachedBackground> backgrounds_;
};

}  // namespace aar
