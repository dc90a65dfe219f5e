// Vulkan instance, physical-device queries and error reporting shared by enumerate_vulkan() and the
// backend (runtime/vulkan/vulkan_backend.h).
#pragma once
#include <vulkan/vulkan.h>

#include <string>
#include <vector>

#include "megavox/device.h"

namespace mv::rt::vulkan {

std::string result_name(VkResult r);
[[noreturn]] void fail(const std::string& what);    // throws mv::Error("Vulkan: " + what)
void check(VkResult r, const std::string& call);   // fail()s naming the call and the result

// A zeroed Vulkan structure with its sType (and chain) set; spelled out once instead of per struct.
template <class T>
T vk(VkStructureType type, void* next = nullptr) {
  T s{};
  s.sType = type;
  s.pNext = next;
  return s;
}

// Shared by enumerate_vulkan() and open_vulkan() so both see the same devices in the same order.
VkResult create_instance(VkInstance* out);
VkResult physicaldevices(VkInstance instance, std::vector<VkPhysicalDevice>& out);

// Everything megavox reads about a physical device. The Vulkan 1.2 structures stay zeroed on older devices.
struct DeviceQuery {
  VkPhysicalDeviceProperties props{};
  VkPhysicalDeviceDriverProperties driver =
      vk<VkPhysicalDeviceDriverProperties>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES);
  VkPhysicalDeviceSubgroupProperties subgroup =
      vk<VkPhysicalDeviceSubgroupProperties>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES);
  VkPhysicalDeviceMaintenance3Properties maintenance3 =
      vk<VkPhysicalDeviceMaintenance3Properties>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES);
  VkPhysicalDeviceFeatures features{};
  VkPhysicalDeviceVulkan12Features features12 =
      vk<VkPhysicalDeviceVulkan12Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES);
  VkPhysicalDeviceMemoryProperties memory{};
  // Compute units where the driver says (VK_NV_shader_sm_builtins, VK_AMD_shader_core_properties); else 0.
  uint32_t compute_units = 0;
};

DeviceQuery query_device(VkPhysicalDevice device);
DeviceInfo describe(const DeviceQuery& q, int index);

}  // namespace mv::rt::vulkan
