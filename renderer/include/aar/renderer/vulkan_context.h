#pragma once
// Headless Vulkan: instance, one physical device with a graphics queue, a
// logical device and a command pool; no surface, no swapchain. Every Vulkan
// call goes through VkCheck, which throws aar::Error with the call's name and
// the VkResult.

#include <vulkan/vulkan.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace aar {

/// Throws aar::Error("<what> failed: VK_ERROR_...") unless result is VK_SUCCESS.
void VkCheck(VkResult result, const char* what);
const char* VkResultName(VkResult result);

struct DeviceInfo {
  std::string name;         ///< e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string driver_name;  ///< e.g. "llvmpipe"
  std::string driver_info;  ///< e.g. "Mesa 22.3.6 (LLVM 15.0.6)"
  std::string api_version;  ///< e.g. "1.3.230"
  uint32_t vendor_id = 0;
  uint32_t device_id = 0;
  std::string device_type;               ///< "cpu", "discrete-gpu", ...
  std::vector<int> color_sample_counts;  ///< native MSAA counts for colour and depth attachments
  bool standard_sample_locations = false;
  float max_anisotropy = 1.0f;  ///< 1 when anisotropic filtering is unavailable
};

struct VulkanContextOptions {
  /// Substring of the device name to pick (case-sensitive); empty = the
  /// AAR_VK_DEVICE environment variable, else the first device, preferring lavapipe
  /// ("llvmpipe") so results match CI unless a GPU is asked for.
  std::string device_filter;
  bool validation = false;  ///< enable VK_LAYER_KHRONOS_validation when installed
};

class VulkanContext {
 public:
  explicit VulkanContext(const VulkanContextOptions& options);
  ~VulkanContext();
  VulkanContext(const VulkanContext&) = delete;
  VulkanContext& operator=(const VulkanContext&) = delete;

  VkDevice device() const { return device_; }
  VkPhysicalDevice physical_device() const { return physical_device_; }
  VkQueue queue() const { return queue_; }
  VkCommandPool command_pool() const { return command_pool_; }
  const DeviceInfo& info() const { return info_; }

  /// A memory type index with `required` properties among `type_bits`,
  /// preferring one that also has `preferred`; throws when none.
  uint32_t FindMemoryType(uint32_t type_bits, VkMemoryPropertyFlags required,
                          VkMemoryPropertyFlags preferred = 0) const;

  /// Records commands with `record`, submits them and waits.
  template <typename F>
  void SubmitAndWait(F&& record) {
    VkCommandBuffer cmd = BeginOneShot();
    record(cmd);
    EndOneShotAndWait(cmd);
  }
  VkCommandBuffer BeginOneShot();
  void EndOneShotAndWait(VkCommandBuffer cmd);

  /// Lists every device the loader sees (for `aar-render devices`).
  static std::vector<DeviceInfo> ListDevices();

 private:
  void Destroy();
  VkInstance instance_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_device_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  uint32_t queue_family_ = 0;
  VkCommandPool command_pool_ = VK_NULL_HANDLE;
  VkCommandBuffer command_buffer_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  VkPhysicalDeviceMemoryProperties memory_properties_{};
  DeviceInfo info_;
};

}  // namespace aar
