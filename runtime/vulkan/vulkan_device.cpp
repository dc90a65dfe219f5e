// Vulkan instance creation, device enumeration and description (declarations in vulkan_device.h).
#include "vulkan_device.h"

#include <algorithm>
#include <cstring>
#include <thread>

#include "backend.h"
#include "megavox/error.h"

namespace mv::rt {
namespace vulkan {

std::string result_name(VkResult r) {
  switch (r) {
#define MV_VK_RESULT(x) \
  case x:               \
    return #x;
    MV_VK_RESULT(VK_SUCCESS)
    MV_VK_RESULT(VK_NOT_READY)
    MV_VK_RESULT(VK_TIMEOUT)
    MV_VK_RESULT(VK_INCOMPLETE)
    MV_VK_RESULT(VK_ERROR_OUT_OF_HOST_MEMORY)
    MV_VK_RESULT(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    MV_VK_RESULT(VK_ERROR_INITIALIZATION_FAILED)
    MV_VK_RESULT(VK_ERROR_DEVICE_LOST)
    MV_VK_RESULT(VK_ERROR_MEMORY_MAP_FAILED)
    MV_VK_RESULT(VK_ERROR_LAYER_NOT_PRESENT)
    MV_VK_RESULT(VK_ERROR_EXTENSION_NOT_PRESENT)
    MV_VK_RESULT(VK_ERROR_FEATURE_NOT_PRESENT)
    MV_VK_RESULT(VK_ERROR_INCOMPATIBLE_DRIVER)
    MV_VK_RESULT(VK_ERROR_TOO_MANY_OBJECTS)
    MV_VK_RESULT(VK_ERROR_FORMAT_NOT_SUPPORTED)
    MV_VK_RESULT(VK_ERROR_FRAGMENTED_POOL)
    MV_VK_RESULT(VK_ERROR_UNKNOWN)
    MV_VK_RESULT(VK_ERROR_OUT_OF_POOL_MEMORY)
    MV_VK_RESULT(VK_ERROR_INVALID_EXTERNAL_HANDLE)
    MV_VK_RESULT(VK_ERROR_FRAGMENTATION)
    MV_VK_RESULT(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
    MV_VK_RESULT(VK_PIPELINE_COMPILE_REQUIRED)
    MV_VK_RESULT(VK_ERROR_INVALID_SHADER_NV)
#undef MV_VK_RESULT
    default:
      return "VkResult " + std::to_string(static_cast<int>(r));
  }
}

[[noreturn]] void fail(const std::string& what) { throw DeviceError("Vulkan: " + what); }

void check(VkResult r, const std::string& call) {
  if (r != VK_SUCCESS) fail(call + " failed (" + result_name(r) + ")");
}

VkResult create_instance(VkInstance* out) {
  uint32_t count = 0;
  VkResult r = vkEnumerateInstanceExtensionProperties(nullptr, &count, nullptr);
  if (r != VK_SUCCESS) return r;
  std::vector<VkExtensionProperties> extensions(count);
  r = vkEnumerateInstanceExtensionProperties(nullptr, &count, extensions.data());
  if (r != VK_SUCCESS && r != VK_INCOMPLETE) return r;
  // Portability drivers (MoltenVK) are only listed when the application opts in.
  const char* portability = VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME;
  const bool has_portability = std::any_of(extensions.begin(), extensions.begin() + count, [&](const auto& e) {
    return std::strcmp(e.extensionName, portability) == 0;
  });

  auto app = vk<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
  app.pApplicationName = "megavox";
  app.apiVersion = VK_API_VERSION_1_2;
  auto ci = vk<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
  ci.pApplicationInfo = &app;
  if (has_portability) {
    ci.flags = VK_INSTANCE_CREATE_ENUMERATE_PORTABILITY_BIT_KHR;
    ci.enabledExtensionCount = 1;
    ci.ppEnabledExtensionNames = &portability;
  }
  return vkCreateInstance(&ci, nullptr, out);
}

VkResult physicaldevices(VkInstance instance, std::vector<VkPhysicalDevice>& out) {
  uint32_t count = 0;
  VkResult r = vkEnumeratePhysicalDevices(instance, &count, nullptr);
  if (r != VK_SUCCESS) return r;
  out.resize(count);
  r = vkEnumeratePhysicalDevices(instance, &count, out.data());
  out.resize(count);
  return r == VK_INCOMPLETE ? VK_SUCCESS : r;
}

namespace {

// Vulkan core does not count compute units; NVIDIA's and AMD's extensions do (SMs; CUs per shader array).
uint32_t vulkan_compute_units(VkPhysicalDevice device) {
  uint32_t count = 0;
  if (vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr) != VK_SUCCESS) return 0;
  std::vector<VkExtensionProperties> extensions(count);
  if (vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data()) != VK_SUCCESS) return 0;
  auto has = [&](const char* name) {
    return std::any_of(extensions.begin(), extensions.end(),
                       [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
  };
  if (has(VK_NV_SHADER_SM_BUILTINS_EXTENSION_NAME)) {
    auto sm = vk<VkPhysicalDeviceShaderSMBuiltinsPropertiesNV>(
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_SM_BUILTINS_PROPERTIES_NV);
    auto props2 = vk<VkPhysicalDeviceProperties2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &sm);
    vkGetPhysicalDeviceProperties2(device, &props2);
    return sm.shaderSMCount;
  }
  if (has(VK_AMD_SHADER_CORE_PROPERTIES_EXTENSION_NAME)) {
    auto core = vk<VkPhysicalDeviceShaderCorePropertiesAMD>(
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_CORE_PROPERTIES_AMD);
    auto props2 = vk<VkPhysicalDeviceProperties2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &core);
    vkGetPhysicalDeviceProperties2(device, &props2);
    return core.shaderEngineCount * core.shaderArraysPerEngineCount * core.computeUnitsPerShaderArray;
  }
  return 0;
}

}  // namespace

DeviceQuery query_device(VkPhysicalDevice device) {
  DeviceQuery q;
  vkGetPhysicalDeviceProperties(device, &q.props);
  const bool v12 = q.props.apiVersion >= VK_API_VERSION_1_2;

  q.subgroup.pNext = &q.maintenance3;
  q.maintenance3.pNext = v12 ? &q.driver : nullptr;
  auto props2 = vk<VkPhysicalDeviceProperties2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &q.subgroup);
  vkGetPhysicalDeviceProperties2(device, &props2);

  auto features2 =
      vk<VkPhysicalDeviceFeatures2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, v12 ? &q.features12 : nullptr);
  vkGetPhysicalDeviceFeatures2(device, &features2);
  q.features = features2.features;
  vkGetPhysicalDeviceMemoryProperties(device, &q.memory);
  // The chain pointed into this object; a returned copy must not carry it.
  q.subgroup.pNext = q.maintenance3.pNext = q.features12.pNext = nullptr;
  q.compute_units = vulkan_compute_units(device);
  return q;
}

DeviceInfo describe(const DeviceQuery& q, int index) {
  DeviceInfo info;
  info.backend = "vulkan";
  info.index = index;
  info.name = q.props.deviceName;
  info.platform = q.driver.driverName[0] ? q.driver.driverName : "Vulkan";
  info.driver = q.driver.driverInfo[0] ? q.driver.driverInfo : std::to_string(q.props.driverVersion);
  info.api_version = std::to_string(VK_API_VERSION_MAJOR(q.props.apiVersion)) + "." +
                     std::to_string(VK_API_VERSION_MINOR(q.props.apiVersion)) + "." +
                     std::to_string(VK_API_VERSION_PATCH(q.props.apiVersion));
  switch (q.props.deviceType) {
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
      info.type = "cpu";
      break;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      info.type = "gpu";
      break;
    default:
      info.type = "other";
      break;
  }
  for (uint32_t i = 0; i < q.memory.memoryHeapCount; ++i)
    if (q.memory.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
      info.global_memory_bytes = std::max<uint64_t>(info.global_memory_bytes, q.memory.memoryHeaps[i].size);
  const VkPhysicalDeviceLimits& limits = q.props.limits;
  info.max_allocation_bytes = q.maintenance3.maxMemoryAllocationSize;
  info.max_binding_bytes = limits.maxStorageBufferRange;
  info.local_memory_bytes = limits.maxComputeSharedMemorySize;
  info.max_work_group_size = limits.maxComputeWorkGroupInvocations;
  info.max_groups = limits.maxComputeWorkGroupCount[0];
  info.max_groups_y = limits.maxComputeWorkGroupCount[1];
  info.subgroup_size = q.subgroup.subgroupSize;
  info.fp64 = q.features.shaderFloat64;
  info.int64 = q.features.shaderInt64;
  info.atomics64 = q.features12.shaderBufferInt64Atomics;
  info.shared_atomics64 = q.features12.shaderSharedInt64Atomics;
  info.vendor = info.platform;
  // llvmpipe's shader compiler ends every loop after 65535 iterations (a guard against hangs), without error.
  if (q.driver.driverID == VK_DRIVER_ID_MESA_LLVMPIPE) info.max_loop_iterations = 65535;
  // A CPU driver (lavapipe) runs a thread per core; a GPU's count comes from its vendor's extension, if any.
  info.compute_units = info.type == "cpu" ? std::max(1u, std::thread::hardware_concurrency()) : q.compute_units;
  info.simd_width = std::max<uint32_t>(1, info.subgroup_size);
  apply_kernel_shape(info, KernelShape::automatic);
  // llvmpipe runs every global load as a loop over the SIMD lanes, and every branch under a lane mask.
  info.cheap_parameter_loads = q.driver.driverID != VK_DRIVER_ID_MESA_LLVMPIPE;
  return info;
}

}  // namespace vulkan

using namespace vulkan;

std::vector<DeviceInfo> enumerate_vulkan() {
  // Devices are listed through one instance kept for the life of the process. Destroying it unloads the drivers,
  // and Mesa 22.3's lavapipe then loses what its one-time initialisation allocated: LeakSanitizer reported it in
  // every process that listed devices (scripts/test.sh --sanitize). Creating it also loads every driver once.
  static const VkInstance instance = [] {
    VkInstance created = VK_NULL_HANDLE;
    return create_instance(&created) == VK_SUCCESS ? created : VK_NULL_HANDLE;
  }();
  std::vector<DeviceInfo> infos;
  if (instance == VK_NULL_HANDLE) return infos;  // no loader or no driver: no Vulkan devices
  std::vector<VkPhysicalDevice> devices;
  if (physicaldevices(instance, devices) == VK_SUCCESS)
    for (size_t i = 0; i < devices.size(); ++i)
      infos.push_back(describe(query_device(devices[i]), static_cast<int>(i)));
  return infos;
}

}  // namespace mv::rt
