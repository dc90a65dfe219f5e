// Vulkan compute backend: plain Vulkan 1.2 C API, one queue, one command buffer recorded lazily.
// Kernels take no descriptor sets: every buffer reaches a shader as a 64-bit buffer device address in the
// push constants (see kernels/common/mv_lang.h), so a binding is never limited by maxStorageBufferRange.
// This file opens the device (instance, queue, command pool, fence) and releases it; the class is declared
// in vulkan_backend.h, its memory, pipelines and commands are in files of their own.
#include <vulkan/vulkan.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "backend.h"
#include "vulkan_backend.h"
#include "vulkan_device.h"

namespace mv::rt {
namespace vulkan {

void VulkanBackend::init(int index) {
  check(create_instance(&instance_), "vkCreateInstance");
  std::vector<VkPhysicalDevice> devices;
  check(physicaldevices(instance_, devices), "vkEnumeratePhysicalDevices");
  if (index < 0 || static_cast<size_t>(index) >= devices.size())
    throw Error("Vulkan: no device vk:" + std::to_string(index) + " (" + std::to_string(devices.size()) + " Vulkan devices)");
  const VkPhysicalDevice physical = devices[index];
  const DeviceQuery q = query_device(physical);
  info_ = describe(q, index);
  memory_ = q.memory;
  max_local_size_ =
      std::min(q.props.limits.maxComputeWorkGroupInvocations, q.props.limits.maxComputeWorkGroupSize[0]);
  max_local_size_y_ = q.props.limits.maxComputeWorkGroupSize[1];
  timestamp_period_ = q.props.limits.timestampPeriod;
  if (!q.features12.bufferDeviceAddress)
    throw Error("Vulkan: device '" + info_.name + "' lacks bufferDeviceAddress (Vulkan 1.2), which every megavox kernel uses");
  if (!q.features.shaderInt64) throw Error("Vulkan: device '" + info_.name + "' lacks shaderInt64, which every megavox kernel uses");

  uint32_t family_count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical, &family_count, nullptr);
  std::vector<VkQueueFamilyProperties> families(family_count);
  vkGetPhysicalDeviceQueueFamilyProperties(physical, &family_count, families.data());
  const auto family = std::find_if(families.begin(), families.end(),
                                   [](const auto& f) { return (f.queueFlags & VK_QUEUE_COMPUTE_BIT) != 0; });
  if (family == families.end()) throw Error("Vulkan: device '" + info_.name + "' has no compute queue");
  const auto family_index = static_cast<uint32_t>(family - families.begin());
  timestamp_bits_ = family->timestampValidBits;

  const float priority = 1.0f;
  auto qi = vk<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
  qi.queueFamilyIndex = family_index;
  qi.queueCount = 1;
  qi.pQueuePriorities = &priority;
  auto features12 = vk<VkPhysicalDeviceVulkan12Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES);
  features12.bufferDeviceAddress = VK_TRUE;
  features12.shaderBufferInt64Atomics = q.features12.shaderBufferInt64Atomics;  // DeviceInfo::atomics64
  features12.shaderSharedInt64Atomics = q.features12.shaderSharedInt64Atomics;
  auto features = vk<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &features12);
  features.features.shaderInt64 = VK_TRUE;
  features.features.shaderFloat64 = q.features.shaderFloat64;
  // A portability (non-conformant) device must have its subset extension enabled when it offers it.
  uint32_t ext_count = 0;
  check(vkEnumerateDeviceExtensionProperties(physical, nullptr, &ext_count, nullptr),
        "vkEnumerateDeviceExtensionProperties");
  std::vector<VkExtensionProperties> extensions(ext_count);
  check(vkEnumerateDeviceExtensionProperties(physical, nullptr, &ext_count, extensions.data()),
        "vkEnumerateDeviceExtensionProperties");
  const char* portability_subset = "VK_KHR_portability_subset";
  const bool has_subset = std::any_of(extensions.begin(), extensions.end(), [&](const auto& e) {
    return std::strcmp(e.extensionName, portability_subset) == 0;
  });
  auto di = vk<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features);
  di.queueCreateInfoCount = 1;
  di.pQueueCreateInfos = &qi;
  di.enabledExtensionCount = has_subset ? 1 : 0;
  di.ppEnabledExtensionNames = &portability_subset;
  check(vkCreateDevice(physical, &di, nullptr, &device_), "vkCreateDevice");
  vkGetDeviceQueue(device_, family_index, 0, &queue_);

  auto pi = vk<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
  pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pi.queueFamilyIndex = family_index;
  check(vkCreateCommandPool(device_, &pi, nullptr, &pool_), "vkCreateCommandPool");
}

void VulkanBackend::release() noexcept {
  if (device_) {
    vkDeviceWaitIdle(device_);
    kernels_.clear();
    for (Submission& s : in_flight_) spare_fences_.push_back(s.fence);
    in_flight_.clear();  // its memory, like the chunks', belongs to device_
    arg_chunks_.clear();
    arg_free_.clear();
    staged_uploads_.clear();
    vkDestroyQueryPool(device_, query_pool_, nullptr);
    for (VkFence f : spare_fences_) vkDestroyFence(device_, f, nullptr);
    vkDestroyCommandPool(device_, pool_, nullptr);  // frees the command buffers
    vkDestroyDevice(device_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
}

}  // namespace vulkan

std::unique_ptr<Backend> open_vulkan(int index, const std::string& kernel_cache) {
  return std::make_unique<vulkan::VulkanBackend>(index, kernel_cache);
}

}  // namespace mv::rt
