// Vulkan compute backend: plain Vulkan 1.2 C API, one queue, one command buffer recorded lazily.
// Kernels take no descriptor sets: every buffer reaches a shader as a 64-bit buffer device address in the
// push constants (see kernels/common/mv_lang.h), so a binding is never limited by maxStorageBufferRange.
#include <vulkan/vulkan.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "backend.h"
#include "vulkan_device.h"
#include "megavox/error.h"

namespace mv::rt {
namespace {

constexpr uint32_t kTimestampQueries = 8192;                      // two per profiled dispatch
constexpr uint64_t kFenceTimeoutNs = 30ull * 60 * 1000000000ull;  // 30 minutes
constexpr uint64_t kStagingBytes = 64ull << 20;                   // chunk size of staged transfers
constexpr VkPipelineStageFlags kWorkStages = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;

using namespace vulkan;

// A VkBuffer bound to its own VkDeviceMemory: arenas, and the staging buffers of unmappable arenas.
struct VulkanArena final : BackendArena {
  VkDevice device = VK_NULL_HANDLE;
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* mapped = nullptr;  // set when the memory is host-visible and coherent: transfers are plain memcpy
  VkDeviceAddress address = 0;
  uint64_t bytes = 0;

  explicit VulkanArena(VkDevice d) : device(d) {}
  VulkanArena(const VulkanArena&) = delete;
  VulkanArena& operator=(const VulkanArena&) = delete;
  // The owner destroys arenas only after finish(): no recorded or running command may still use them.
  ~VulkanArena() override {
    if (mapped) vkUnmapMemory(device, memory);
    vkDestroyBuffer(device, buffer, nullptr);
    vkFreeMemory(device, memory, nullptr);
  }
};

struct VulkanBuffer final : BackendBuffer {
  VulkanArena* arena = nullptr;
  uint64_t offset = 0;
  uint64_t bytes = 0;
  VkDeviceAddress address = 0;
};

struct VulkanKernel final : BackendKernel {
  VkDevice device;
  std::string name;
  VkShaderModule module = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  std::unordered_map<uint32_t, VkPipeline> pipelines;  // by local size

  VulkanKernel(VkDevice d, std::string n) : device(d), name(std::move(n)) {}
  VulkanKernel(const VulkanKernel&) = delete;
  VulkanKernel& operator=(const VulkanKernel&) = delete;
  ~VulkanKernel() override {
    for (const auto& [size, pipeline] : pipelines) vkDestroyPipeline(device, pipeline, nullptr);
    vkDestroyPipelineLayout(device, layout, nullptr);
    vkDestroyShaderModule(device, module, nullptr);
  }
};

VulkanBuffer& as_vk(BackendBuffer& b) { return static_cast<VulkanBuffer&>(b); }

// Index of a memory type in `allowed` with all of `flags` whose heap can hold `bytes`; -1 if none.
int find_memory_type(const VkPhysicalDeviceMemoryProperties& memory, uint32_t allowed, VkMemoryPropertyFlags flags,
                     uint64_t bytes) {
  for (uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
    const VkMemoryType& type = memory.memoryTypes[i];
    if ((allowed & (1u << i)) && (type.propertyFlags & flags) == flags &&
        memory.memoryHeaps[type.heapIndex].size >= bytes)
      return static_cast<int>(i);
  }
  return -1;
}

class VulkanBackend final : public Backend {
 public:
  explicit VulkanBackend(int index) {
    try {
      init(index);
    } catch (...) {
      release();
      throw;
    }
  }
  ~VulkanBackend() override { release(); }
  VulkanBackend(const VulkanBackend&) = delete;
  VulkanBackend& operator=(const VulkanBackend&) = delete;

  const DeviceInfo& info() const override { return info_; }

  std::unique_ptr<BackendArena> create_arena(uint64_t bytes) override {
    if (bytes == 0 || bytes > info_.max_allocation_bytes)
      fail("cannot allocate an arena of " + std::to_string(bytes) + " bytes (the device allows 1 to " +
           std::to_string(info_.max_allocation_bytes) + " bytes per allocation)");
    constexpr VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                         VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                         VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    // Device-local memory the host can map (CPU devices, ReBAR GPUs) avoids staging copies entirely.
    return allocate(bytes, usage,
                    {VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                         VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                     VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT});
  }

  std::unique_ptr<BackendBuffer> create_buffer(BackendArena& arena, uint64_t offset, uint64_t bytes) override {
    auto& a = static_cast<VulkanArena&>(arena);
    if (offset > a.bytes || bytes > a.bytes - offset)
      fail("buffer [" + std::to_string(offset) + ", +" + std::to_string(bytes) + ") lies outside its arena of " +
           std::to_string(a.bytes) + " bytes");
    auto b = std::make_unique<VulkanBuffer>();
    b->arena = &a;
    b->offset = offset;
    b->bytes = bytes;
    b->address = a.address + offset;
    return b;
  }

  void upload(BackendBuffer& dst, uint64_t offset, const void* src, uint64_t bytes) override {
    transfer(as_vk(dst), offset, bytes, src, nullptr);
  }
  void download(BackendBuffer& src, uint64_t offset, void* dst, uint64_t bytes) override {
    transfer(as_vk(src), offset, bytes, nullptr, dst);
  }

  void fill(BackendBuffer& dst, uint64_t offset, uint64_t bytes, uint32_t pattern) override {
    VulkanBuffer& b = as_vk(dst);
    check_range(b, offset, bytes, "fill");
    if ((b.offset + offset) % 4 || bytes % 4)
      fail("fill needs offset and size in multiples of 4 bytes (got offset " + std::to_string(b.offset + offset) +
           ", " + std::to_string(bytes) + " bytes)");
    if (bytes == 0) return;
    vkCmdFillBuffer(recording(), b.arena->buffer, b.offset + offset, bytes, pattern);
  }

  void copy(BackendBuffer& src, uint64_t src_offset, BackendBuffer& dst, uint64_t dst_offset, uint64_t bytes) override {
    VulkanBuffer& s = as_vk(src);
    VulkanBuffer& d = as_vk(dst);
    check_range(s, src_offset, bytes, "copy source");
    check_range(d, dst_offset, bytes, "copy destination");
    if (bytes == 0) return;
    const VkBufferCopy region{s.offset + src_offset, d.offset + dst_offset, bytes};
    // Vulkan forbids overlapping regions within one buffer.
    if (s.arena == d.arena && region.srcOffset < region.dstOffset + bytes &&
        region.dstOffset < region.srcOffset + bytes)
      fail("copy of " + std::to_string(bytes) + " bytes between overlapping ranges");
    vkCmdCopyBuffer(recording(), s.arena->buffer, d.arena->buffer, 1, &region);
  }

  BackendKernel& kernel(const KernelDesc& desc) override {
    if (auto it = kernels_.find(desc.name); it != kernels_.end()) return *it->second;
    const std::string what = "kernel '" + desc.name + "': ";
    // Invalid SPIR-V is undefined behaviour (drivers may crash on it) and lavapipe only rejects it at pipeline
    // creation, i.e. at first dispatch: catch the obvious cases here, when the kernel is asked for.
    if (!desc.spirv || desc.spirv_words < 5)
      fail(what + "no SPIR-V module (" + std::to_string(desc.spirv ? desc.spirv_words : 0) + " words)");
    if (desc.spirv[0] != 0x07230203u) {
      char magic[16];
      std::snprintf(magic, sizeof(magic), "0x%08x", desc.spirv[0]);
      fail(what + "not a SPIR-V module (magic number " + magic + ", expected 0x07230203)");
    }

    auto k = std::make_unique<VulkanKernel>(device_, desc.name);
    auto mi = vk<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
    mi.codeSize = desc.spirv_words * sizeof(uint32_t);
    mi.pCode = desc.spirv;
    check(vkCreateShaderModule(device_, &mi, nullptr, &k->module), what + "vkCreateShaderModule");

    const VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, static_cast<uint32_t>(kMaxPushBytes)};
    auto li = vk<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
    li.pushConstantRangeCount = 1;
    li.pPushConstantRanges = &range;
    check(vkCreatePipelineLayout(device_, &li, nullptr, &k->layout), what + "vkCreatePipelineLayout");
    return *kernels_.emplace(desc.name, std::move(k)).first->second;
  }

  void dispatch(BackendKernel& k, uint32_t groups, uint32_t local_size, std::span<BackendBuffer* const> buffers,
                const void* params, size_t params_bytes) override {
    auto& kernel = static_cast<VulkanKernel&>(k);
    if (groups == 0) return;
    if (groups > info_.max_groups)
      fail("kernel '" + kernel.name + "': " + std::to_string(groups) + " groups exceed the device limit of " +
           std::to_string(info_.max_groups));
    const size_t push_bytes = 8 * buffers.size() + params_bytes;
    if (push_bytes > kMaxPushBytes)
      fail("kernel '" + kernel.name + "': " + std::to_string(buffers.size()) + " buffers and " +
           std::to_string(params_bytes) + " parameter bytes exceed the " + std::to_string(kMaxPushBytes) +
           "-byte push-constant limit");
    std::array<unsigned char, kMaxPushBytes> push{};
    for (size_t i = 0; i < buffers.size(); ++i) {
      // A null (empty) buffer passes address 0, as OpenCL passes a null cl_mem: the kernel must not touch it.
      const VkDeviceAddress address = buffers[i] ? as_vk(*buffers[i]).address : 0;
      std::memcpy(push.data() + 8 * i, &address, sizeof(address));
    }
    if (params_bytes) std::memcpy(push.data() + 8 * buffers.size(), params, params_bytes);

    const VkPipeline pipeline = pipeline_for(kernel, local_size);
    const bool timed = profiling_;
    if (timed && queries_used_ + 2 > kTimestampQueries) finish();
    const VkCommandBuffer cmd = recording();
    if (timed) {
      if (queries_used_ == 0) vkCmdResetQueryPool(cmd, query_pool_, 0, kTimestampQueries);
      vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, query_pool_, queries_used_++);
    }
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    if (push_bytes)  // Vulkan wants a multiple of 4; the padding is zero and still within kMaxPushBytes
      vkCmdPushConstants(cmd, kernel.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0,
                         static_cast<uint32_t>((push_bytes + 3) & ~size_t{3}), push.data());
    vkCmdDispatch(cmd, groups, 1, 1);
    if (timed) {
      vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, query_pool_, queries_used_++);
      query_names_.push_back(kernel.name);
    }
  }

  void barrier() override {
    auto mb = vk<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
    mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                       VK_ACCESS_TRANSFER_WRITE_BIT;
    vkCmdPipelineBarrier(recording(), kWorkStages, kWorkStages, 0, 1, &mb, 0, nullptr, 0, nullptr);
  }

  void finish() override {
    if (!recording_) return;
    recording_ = false;
    // Taken now so that a failed submission cannot leave stale queries behind for the next recording.
    const uint32_t queries = std::exchange(queries_used_, 0);
    const std::vector<std::string> names = std::exchange(query_names_, {});

    // A fence wait alone does not make device writes visible to the host; this barrier does.
    auto to_host = vk<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
    to_host.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cmd_, kWorkStages, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &to_host, 0, nullptr, 0, nullptr);
    check(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");

    auto si = vk<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd_;
    check(vkQueueSubmit(queue_, 1, &si, fence_), "vkQueueSubmit");
    const VkResult waited = vkWaitForFences(device_, 1, &fence_, VK_TRUE, kFenceTimeoutNs);
    if (waited == VK_TIMEOUT) fail("device work did not finish within 30 minutes on " + info_.name);
    check(waited, "vkWaitForFences");
    check(vkResetFences(device_, 1, &fence_), "vkResetFences");
    check(vkResetCommandBuffer(cmd_, 0), "vkResetCommandBuffer");
    if (queries) collect_timings(queries, names);
  }

  void set_profiling(bool on) override {
    profiling_ = on && timestamp_bits_ > 0;  // a queue family without timestamps yields no timings
    if (profiling_ && !query_pool_) {
      auto qi = vk<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
      qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
      qi.queryCount = kTimestampQueries;
      check(vkCreateQueryPool(device_, &qi, nullptr, &query_pool_), "vkCreateQueryPool");
    }
  }

  std::vector<KernelTiming> take_timings() override { return std::exchange(timings_, {}); }

 private:
  void init(int index) {
    check(create_instance(&instance_), "vkCreateInstance");
    std::vector<VkPhysicalDevice> devices;
    check(physicaldevices(instance_, devices), "vkEnumeratePhysicalDevices");
    if (index < 0 || static_cast<size_t>(index) >= devices.size())
      fail("no device vk:" + std::to_string(index) + " (" + std::to_string(devices.size()) + " Vulkan devices)");
    const VkPhysicalDevice physical = devices[index];
    const DeviceQuery q = query_device(physical);
    info_ = describe(q, index);
    memory_ = q.memory;
    max_local_size_ =
        std::min(q.props.limits.maxComputeWorkGroupInvocations, q.props.limits.maxComputeWorkGroupSize[0]);
    timestamp_period_ = q.props.limits.timestampPeriod;
    if (!q.features12.bufferDeviceAddress)
      fail("device '" + info_.name + "' lacks bufferDeviceAddress (Vulkan 1.2), which every megavox kernel uses");
    if (!q.features.shaderInt64) fail("device '" + info_.name + "' lacks shaderInt64, which every megavox kernel uses");

    uint32_t family_count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &family_count, nullptr);
    std::vector<VkQueueFamilyProperties> families(family_count);
    vkGetPhysicalDeviceQueueFamilyProperties(physical, &family_count, families.data());
    const auto family = std::find_if(families.begin(), families.end(),
                                     [](const auto& f) { return (f.queueFlags & VK_QUEUE_COMPUTE_BIT) != 0; });
    if (family == families.end()) fail("device '" + info_.name + "' has no compute queue");
    const auto family_index = static_cast<uint32_t>(family - families.begin());
    timestamp_bits_ = family->timestampValidBits;

    const float priority = 1.0f;
    auto qi = vk<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
    qi.queueFamilyIndex = family_index;
    qi.queueCount = 1;
    qi.pQueuePriorities = &priority;
    auto features12 = vk<VkPhysicalDeviceVulkan12Features>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES);
    features12.bufferDeviceAddress = VK_TRUE;
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
    auto ai = vk<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
    ai.commandPool = pool_;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    check(vkAllocateCommandBuffers(device_, &ai, &cmd_), "vkAllocateCommandBuffers");
    auto fi = vk<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
    check(vkCreateFence(device_, &fi, nullptr, &fence_), "vkCreateFence");
  }

  // Also undoes a partial init(): every handle is either valid or null.
  void release() noexcept {
    if (device_) {
      vkDeviceWaitIdle(device_);
      kernels_.clear();
      vkDestroyQueryPool(device_, query_pool_, nullptr);
      vkDestroyFence(device_, fence_, nullptr);
      vkDestroyCommandPool(device_, pool_, nullptr);  // frees cmd_
      vkDestroyDevice(device_, nullptr);
    }
    if (instance_) vkDestroyInstance(instance_, nullptr);
  }

  VkCommandBuffer recording() {
    if (!recording_) {
      auto bi = vk<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
      bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
      check(vkBeginCommandBuffer(cmd_, &bi), "vkBeginCommandBuffer");
      recording_ = true;
    }
    return cmd_;
  }

  std::unique_ptr<VulkanArena> allocate(uint64_t bytes, VkBufferUsageFlags usage,
                                        std::initializer_list<VkMemoryPropertyFlags> preferences) {
    auto a = std::make_unique<VulkanArena>(device_);
    a->bytes = bytes;
    auto bi = vk<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
    bi.size = bytes;
    bi.usage = usage;
    bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    check(vkCreateBuffer(device_, &bi, nullptr, &a->buffer), "vkCreateBuffer of " + std::to_string(bytes) + " bytes");
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device_, a->buffer, &req);

    const bool device_address = usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
    auto flags = vk<VkMemoryAllocateFlagsInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO);
    flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    auto ai = vk<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, device_address ? &flags : nullptr);
    ai.allocationSize = req.size;
    // Try each preference in turn: a small mappable heap (non-ReBAR GPUs) may refuse what device memory holds.
    VkResult r = VK_ERROR_OUT_OF_DEVICE_MEMORY;
    for (VkMemoryPropertyFlags wanted : preferences) {
      const int type = find_memory_type(memory_, req.memoryTypeBits, wanted, req.size);
      if (type < 0) continue;
      ai.memoryTypeIndex = static_cast<uint32_t>(type);
      r = vkAllocateMemory(device_, &ai, nullptr, &a->memory);
      if (r == VK_SUCCESS) break;
    }
    if (r != VK_SUCCESS)
      fail("cannot allocate " + std::to_string(bytes) + " bytes of device memory on " + info_.name + " (" +
           result_name(r) + ")");
    check(vkBindBufferMemory(device_, a->buffer, a->memory, 0), "vkBindBufferMemory");

    constexpr VkMemoryPropertyFlags mappable =
        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    if ((memory_.memoryTypes[ai.memoryTypeIndex].propertyFlags & mappable) == mappable)
      check(vkMapMemory(device_, a->memory, 0, VK_WHOLE_SIZE, 0, &a->mapped), "vkMapMemory");
    if (device_address) {
      auto address_info = vk<VkBufferDeviceAddressInfo>(VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO);
      address_info.buffer = a->buffer;
      a->address = vkGetBufferDeviceAddress(device_, &address_info);
    }
    return a;
  }

  static void check_range(const VulkanBuffer& b, uint64_t offset, uint64_t bytes, const char* what) {
    if (offset > b.bytes || bytes > b.bytes - offset)
      fail(std::string(what) + " of " + std::to_string(bytes) + " bytes at offset " + std::to_string(offset) +
           " overruns a buffer of " + std::to_string(b.bytes) + " bytes");
  }

  // Exactly one of `from_host` (upload) and `to_host` (download) is set.
  void transfer(VulkanBuffer& b, uint64_t offset, uint64_t bytes, const void* from_host, void* to_host) {
    check_range(b, offset, bytes, from_host ? "upload" : "download");
    if (bytes == 0) return;
    finish();
    VulkanArena& arena = *b.arena;
    const uint64_t at = b.offset + offset;
    if (arena.mapped) {
      char* device = static_cast<char*>(arena.mapped) + at;
      if (from_host) std::memcpy(device, from_host, bytes);
      else if (to_host) std::memcpy(to_host, device, bytes);
      return;
    }
    const auto staging =
        allocate(std::min(bytes, kStagingBytes), VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                 {VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT});
    for (uint64_t done = 0; done < bytes; done += staging->bytes) {
      const uint64_t chunk = std::min(staging->bytes, bytes - done);
      if (from_host) {
        std::memcpy(staging->mapped, static_cast<const char*>(from_host) + done, chunk);
        const VkBufferCopy region{0, at + done, chunk};
        vkCmdCopyBuffer(recording(), staging->buffer, arena.buffer, 1, &region);
        finish();
      } else {
        const VkBufferCopy region{at + done, 0, chunk};
        vkCmdCopyBuffer(recording(), arena.buffer, staging->buffer, 1, &region);
        finish();
        std::memcpy(static_cast<char*>(to_host) + done, staging->mapped, chunk);
      }
    }
  }

  VkPipeline pipeline_for(VulkanKernel& kernel, uint32_t local_size) {
    if (auto it = kernel.pipelines.find(local_size); it != kernel.pipelines.end()) return it->second;
    if (local_size == 0 || local_size > max_local_size_)
      fail("kernel '" + kernel.name + "': local size " + std::to_string(local_size) +
           " is outside the device range 1.." + std::to_string(max_local_size_));
    const VkSpecializationMapEntry entry{0, 0, sizeof(uint32_t)};  // constant_id 0 = local_size_x
    const VkSpecializationInfo spec{1, &entry, sizeof(uint32_t), &local_size};
    auto ci = vk<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
    ci.stage = vk<VkPipelineShaderStageCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
    ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    ci.stage.module = kernel.module;
    ci.stage.pName = "main";
    ci.stage.pSpecializationInfo = &spec;
    ci.layout = kernel.layout;
    VkPipeline pipeline = VK_NULL_HANDLE;
    check(vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline),
          "kernel '" + kernel.name + "': vkCreateComputePipelines for local size " + std::to_string(local_size));
    kernel.pipelines.emplace(local_size, pipeline);
    return pipeline;
  }

  void collect_timings(uint32_t queries, const std::vector<std::string>& names) {
    std::vector<uint64_t> ticks(queries);
    check(vkGetQueryPoolResults(device_, query_pool_, 0, queries, ticks.size() * sizeof(uint64_t), ticks.data(),
                                sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
          "vkGetQueryPoolResults");
    const uint64_t mask = timestamp_bits_ >= 64 ? ~uint64_t{0} : (uint64_t{1} << timestamp_bits_) - 1;
    for (size_t i = 0; i < names.size(); ++i) {
      const uint64_t delta = (ticks[2 * i + 1] - ticks[2 * i]) & mask;  // the mask absorbs counter wrap-around
      timings_.push_back({names[i], static_cast<uint64_t>(static_cast<double>(delta) * timestamp_period_)});
    }
  }

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;
  VkFence fence_ = VK_NULL_HANDLE;
  bool recording_ = false;

  DeviceInfo info_;
  VkPhysicalDeviceMemoryProperties memory_{};
  uint32_t max_local_size_ = 0;
  std::unordered_map<std::string, std::unique_ptr<VulkanKernel>> kernels_;

  bool profiling_ = false;
  uint32_t timestamp_bits_ = 0;
  float timestamp_period_ = 1.0f;
  VkQueryPool query_pool_ = VK_NULL_HANDLE;
  uint32_t queries_used_ = 0;
  std::vector<std::string> query_names_;  // kernel of each timestamp pair in the current recording
  std::vector<KernelTiming> timings_;
};

}  // namespace

std::unique_ptr<Backend> open_vulkan(int index) { return std::make_unique<VulkanBackend>(index); }

}  // namespace mv::rt
