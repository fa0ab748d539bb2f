#include "aar/renderer/vulkan_context.h"

#include <cstdlib>
#include <cstring>

#include "aar/error.h"

namespace aar {
namespace {

VkInstance CreateInstance(bool validation) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "aar-render";
  app.apiVersion = VK_API_VERSION_1_1;
  std::vector<const char*> layers;
  if (validation) {
    uint32_t count = 0;
    vkEnumerateInstanceLayerProperties(&count, nullptr);
    std::vector<VkLayerProperties> props(count);
    vkEnumerateInstanceLayerProperties(&count, props.data());
    for (const auto& p : props) {
      if (std::strcmp(p.layerName, "VK_LAYER_KHRONOS_validation") == 0) layers.push_back("VK_LAYER_KHRONOS_validation");
    }
  }
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &app;
  info.enabledLayerCount = static_cast<uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  VkInstance instance = VK_NULL_HANDLE;
  const VkResult result = vkCreateInstance(&info, nullptr, &instance);
  if (result == VK_ERROR_INCOMPATIBLE_DRIVER || result == VK_ERROR_INITIALIZATION_FAILED) {
    throw Error(std::string("no Vulkan device: vkCreateInstance returned ") + VkResultName(result) +
                " (install mesa-vulkan-drivers for the lavapipe CPU device)");
  }
  VkCheck(result, "vkCreateInstance");
  return instance;
}

std::string VersionString(uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
         std::to_string(VK_API_VERSION_PATCH(v));
}

DeviceInfo DescribeDevice(VkPhysicalDevice device) {
  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  props2.pNext = &driver;
  vkGetPhysicalDeviceProperties2(device, &props2);
  const VkPhysicalDeviceProperties& p = props2.properties;
  VkPhysicalDeviceFeatures features{};
  vkGetPhysicalDeviceFeatures(device, &features);
  DeviceInfo info;
  info.name = p.deviceName;
  info.driver_name = driver.driverName;
  info.driver_info = driver.driverInfo;
  info.api_version = VersionString(p.apiVersion);
  info.vendor_id = p.vendorID;
  info.device_id = p.deviceID;
  switch (p.deviceType) {
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      info.device_type = "cpu";
      break;
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      info.device_type = "discrete-gpu";
      break;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      info.device_type = "integrated-gpu";
      break;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      info.device_type = "virtual-gpu";
      break;
    default:
      info.device_type = "other";
      break;
  }
  const VkSampleCountFlags counts = p.limits.framebufferColorSampleCounts & p.limits.framebufferDepthSampleCounts;
  for (int n = 1; n <= 64; n *= 2) {
    if (counts & static_cast<VkSampleCountFlags>(n)) info.color_sample_counts.push_back(n);
  }
  info.standard_sample_locations = p.limits.standardSampleLocations == VK_TRUE;
  info.max_anisotropy = features.samplerAnisotropy ? std::min(16.0f, p.limits.maxSamplerAnisotropy) : 1.0f;
  return info;
}

std::vector<VkPhysicalDevice> EnumerateDevices(VkInstance instance) {
  uint32_t count = 0;
  VkCheck(vkEnumeratePhysicalDevices(instance, &count, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(count);
  VkCheck(vkEnumeratePhysicalDevices(instance, &count, devices.data()), "vkEnumeratePhysicalDevices");
  return devices;
}

}  // namespace

const char* VkResultName(VkResult result) {
  switch (result) {
    case VK_SUCCESS:
      return "VK_SUCCESS";
    case VK_NOT_READY:
      return "VK_NOT_READY";
    case VK_TIMEOUT:
      return "VK_TIMEOUT";
    case VK_INCOMPLETE:
      return "VK_INCOMPLETE";
    case VK_ERROR_OUT_OF_HOST_MEMORY:
      return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
      return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED:
      return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST:
      return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED:
      return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT:
      return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT:
      return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT:
      return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER:
      return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS:
      return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_FORMAT_NOT_SUPPORTED:
      return "VK_ERROR_FORMAT_NOT_SUPPORTED";
    default:
      return "VK_ERROR_(other)";
  }
}

void VkCheck(VkResult result, const char* what) {
  if (result != VK_SUCCESS) throw Error(std::string(what) + " failed: " + VkResultName(result));
}

std::vector<DeviceInfo> VulkanContext::ListDevices() {
  VkInstance instance = CreateInstance(false);
  std::vector<DeviceInfo> infos;
  for (VkPhysicalDevice d : EnumerateDevices(instance)) infos.push_back(DescribeDevice(d));
  vkDestroyInstance(instance, nullptr);
  return infos;
}

VulkanContext::VulkanContext(const VulkanContextOptions& options) {
  instance_ = CreateInstance(options.validation);
  try {
    const std::vector<VkPhysicalDevice> devices = EnumerateDevices(instance_);
    if (devices.empty())
      throw Error("no Vulkan device found (install mesa-vulkan-drivers for the lavapipe CPU device)");
    std::string filter = options.device_filter;
    if (filter.empty()) {
      if (const char* env = std::getenv("AAR_VK_DEVICE")) filter = env;
    }
    std::string names;
    for (VkPhysicalDevice d : devices) {
      const DeviceInfo info = DescribeDevice(d);
      names += (names.empty() ? "" : ", ") + info.name;
      const bool match = filter.empty() ? info.name.find("llvmpipe") != std::string::npos
                                        : info.name.find(filter) != std::string::npos;
      if (match && physical_device_ == VK_NULL_HANDLE) physical_device_ = d;
    }
    if (physical_device_ == VK_NULL_HANDLE) {
      if (!filter.empty()) throw Error("no Vulkan device matches '" + filter + "' (devices: " + names + ")");
      physical_device_ = devices.front();
    }
    info_ = DescribeDevice(physical_device_);

    uint32_t family_count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_device_, &family_count, nullptr);
    std::vector<VkQueueFamilyProperties> families(family_count);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_device_, &family_count, families.data());
    bool found = false;
    for (uint32_t i = 0; i < family_count && !found; ++i) {
      if (families[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) {
        queue_family_ = i;
        found = true;
      }
    }
    if (!found) throw Error("Vulkan device '" + info_.name + "' has no graphics queue");

    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queue_info{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    queue_info.queueFamilyIndex = queue_family_;
    queue_info.queueCount = 1;
    queue_info.pQueuePriorities = &priority;
    VkPhysicalDeviceFeatures features{};
    features.samplerAnisotropy = info_.max_anisotropy > 1.0f ? VK_TRUE : VK_FALSE;
    VkDeviceCreateInfo device_info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    device_info.queueCreateInfoCount = 1;
    device_info.pQueueCreateInfos = &queue_info;
    device_info.pEnabledFeatures = &features;
    VkCheck(vkCreateDevice(physical_device_, &device_info, nullptr, &device_), "vkCreateDevice");
    vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
    vkGetPhysicalDeviceMemoryProperties(physical_device_, &memory_properties_);

    VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool_info.queueFamilyIndex = queue_family_;
    VkCheck(vkCreateCommandPool(device_, &pool_info, nullptr, &command_pool_), "vkCreateCommandPool");
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = command_pool_;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCheck(vkAllocateCommandBuffers(device_, &alloc, &command_buffer_), "vkAllocateCommandBuffers");
    VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkCheck(vkCreateFence(device_, &fence_info, nullptr, &fence_), "vkCreateFence");
  } catch (...) {
    Destroy();
    throw;
  }
}

VulkanContext::~VulkanContext() { Destroy(); }

void VulkanContext::Destroy() {
  if (device_ != VK_NULL_HANDLE) {
    vkDeviceWaitIdle(device_);
    if (fence_ != VK_NULL_HANDLE) vkDestroyFence(device_, fence_, nullptr);
    if (command_pool_ != VK_NULL_HANDLE) vkDestroyCommandPool(device_, command_pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
    device_ = VK_NULL_HANDLE;
  }
  if (instance_ != VK_NULL_HANDLE) {
    vkDestroyInstance(instance_, nullptr);
    instance_ = VK_NULL_HANDLE;
  }
}

uint32_t VulkanContext::FindMemoryType(uint32_t type_bits, VkMemoryPropertyFlags required,
                                       VkMemoryPropertyFlags preferred) const {
  for (int pass = 0; pass < 2; ++pass) {
    const VkMemoryPropertyFlags wanted = pass == 0 ? (required | preferred) : required;
    for (uint32_t i = 0; i < memory_properties_.memoryTypeCount; ++i) {
      if ((type_bits & (1u << i)) && (memory_properties_.memoryTypes[i].propertyFlags & wanted) == wanted) return i;
    }
  }
  throw Error("Vulkan device '" + info_.name + "' has no suitable memory type");
}

VkCommandBuffer VulkanContext::BeginOneShot() {
  VkCheck(vkResetCommandBuffer(command_buffer_, 0), "vkResetCommandBuffer");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  VkCheck(vkBeginCommandBuffer(command_buffer_, &begin), "vkBeginCommandBuffer");
  return command_buffer_;
}

void VulkanContext::EndOneShotAndWait(VkCommandBuffer cmd) {
  VkCheck(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cmd;
  VkCheck(vkResetFences(device_, 1, &fence_), "vkResetFences");
  VkCheck(vkQueueSubmit(queue_, 1, &submit, fence_), "vkQueueSubmit");
  VkCheck(vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX), "vkWaitForFences");
}

}  // namespace aar
