#pragma once
// The sun's depth maps on the GPU for scene.frag's AAR_SHADOWS variants
// (docs/rendering.md, "Shadows"): per slot (one per instant of an exposure)
// the sun camera's depth image and the uniform block that says where the
// sun camera and the viewing camera are, bound as descriptor set 1.

#include <vulkan/vulkan.h>

#include <Eigen/Geometry>
#include <cstddef>
#include <nlohmann/json.hpp>
#include <vector>

#include "aar/image.h"
#include "aar/renderer/gpu_resources.h"
#include "aar/renderer/vulkan_context.h"
#include "aar/rig.h"

namespace aar {

/// The depth bias scene.frag subtracts before it calls a surface shadowed:
/// a constant for the depths' float rounding at kSunCameraDistanceM (about
/// 1 mm, twice over) and the facets of the models' meshes, and per unit of
/// the surface's slope to the sun the 1.5 texels between a point and the
/// farthest of the four texels it reads.
inline constexpr float kShadowBiasM = 0.02f;
inline constexpr float kShadowSlopeBiasTexels = 1.5f;

/// The manifest's frames.shadows: the method and its constants, for maps of
/// width x height texels.
nlohmann::json ShadowsJson(int width, int height);

class ShadowMaps {
 public:
  /// Maps of width x height texels (the renderer's image size).
  ShadowMaps(VulkanContext& context, int width, int height);
  ~ShadowMaps();
  ShadowMaps(const ShadowMaps&) = delete;
  ShadowMaps& operator=(const ShadowMaps&) = delete;

  /// The layout of set 1: the depth map (binding 0) and the uniform block (binding 1).
  VkDescriptorSetLayout layout() const { return layout_; }
  /// Uploads the sun camera's view (its depth; 0 where no surface) into `slot`.
  void Upload(size_t slot, const GroundTruthImage& sun_view, const Camera& sun_camera);
  /// The set of `slot` with its uniform block written for a view from
  /// `camera_centre_in_tanker`; valid until the slot's next Bind or Upload.
  VkDescriptorSet Bind(size_t slot, const Eigen::Vector3d& camera_centre_in_tanker);

 private:
  struct Slot {
    GpuImage depth;
    GpuBuffer staging;
    GpuBuffer uniforms;
    VkDescriptorSet set = VK_NULL_HANDLE;
    Camera sun_camera;
  };
  Slot& SlotAt(size_t slot);

  VulkanContext& context_;
  int width_, height_;
  VkDescriptorSetLayout layout_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkSampler sampler_ = VK_NULL_HANDLE;
  std::vector<Slot> slots_;
};

}  // namespace aar
