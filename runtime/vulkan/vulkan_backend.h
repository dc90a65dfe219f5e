// The Vulkan compute backend's class and the objects it hands out, declared once for the files that
// implement it: vulkan_backend.cpp (device setup), vulkan_memory.cpp (arenas, buffers, transfers),
// vulkan_pipelines.cpp (kernels and their pipelines) and vulkan_commands.cpp (recording, submission,
// timestamps). Internal to runtime/vulkan; everything else reaches it through open_vulkan() (backend.h).
#pragma once
#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <deque>
#include <initializer_list>
#include <memory>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "backend.h"
#include "kernel_cache.h"
#include "vulkan_device.h"

namespace mv::rt::vulkan {

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

struct VulkanBuffer final : BackendBuffer {  // a range of an arena
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
  bool args_in_buffer = false;  // push one address; the arguments sit in a parameter buffer (MV_ARGS_BUFFER)
  std::string cache_key;        // of the module on this device and driver (KernelCache::key)
  std::unordered_map<uint64_t, VkPipeline> pipelines;  // by work-group size: x | y << 32

  VulkanKernel(VkDevice d, std::string n) : device(d), name(std::move(n)) {}
  VulkanKernel(const VulkanKernel&) = delete;
  VulkanKernel& operator=(const VulkanKernel&) = delete;
  ~VulkanKernel() override {
    for (const auto& [size, pipeline] : pipelines) vkDestroyPipeline(device, pipeline, nullptr);
    vkDestroyPipelineLayout(device, layout, nullptr);
    vkDestroyShaderModule(device, module, nullptr);
  }
};

inline VulkanBuffer& as_vk(BackendBuffer& b) { return static_cast<VulkanBuffer&>(b); }

class VulkanBackend final : public Backend {
 public:
  VulkanBackend(int index, const std::string& kernel_cache) : cache_(kernel_cache) {
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

  // vulkan_memory.cpp
  std::unique_ptr<BackendArena> create_arena(uint64_t bytes) override;
  std::unique_ptr<BackendBuffer> create_buffer(BackendArena& arena, uint64_t offset, uint64_t bytes) override;
  const void* host_pointer(BackendBuffer& buffer) const override;
  void upload(BackendBuffer& dst, uint64_t offset, const void* src, uint64_t bytes) override;
  void download(BackendBuffer& src, uint64_t offset, void* dst, uint64_t bytes) override;
  void upload_async(BackendBuffer& dst, uint64_t offset, const void* src, uint64_t bytes) override;
  void fill(BackendBuffer& dst, uint64_t offset, uint64_t bytes, uint32_t pattern) override;
  void copy(BackendBuffer& src, uint64_t src_offset, BackendBuffer& dst, uint64_t dst_offset, uint64_t bytes) override;

  // vulkan_pipelines.cpp
  BackendKernel& kernel(const KernelDesc& desc) override;

  // vulkan_commands.cpp
  void dispatch(BackendKernel& k, const LaunchGrid& grid, std::span<BackendBuffer* const> buffers,
                const void* params, size_t params_bytes) override;
  void barrier() override;
  uint64_t submit() override;
  void wait(uint64_t mark) override;
  void finish() override { wait(submit()); }
  void set_profiling(bool on) override;
  std::vector<KernelTiming> take_timings() override { return std::exchange(timings_, {}); }

 private:
  // vulkan_backend.cpp
  void init(int index);
  // Also undoes a partial init(): every handle is either valid or null.
  void release() noexcept;

  // vulkan_memory.cpp
  std::unique_ptr<VulkanArena> allocate(uint64_t bytes, VkBufferUsageFlags usage,
                                        std::initializer_list<VkMemoryPropertyFlags> preferences);
  static void check_range(const VulkanBuffer& b, uint64_t offset, uint64_t bytes, const char* what);
  // Exactly one of `from_host` (upload) and `to_host` (download) is set.
  void transfer(VulkanBuffer& b, uint64_t offset, uint64_t bytes, const void* from_host, void* to_host);

  // vulkan_pipelines.cpp
  VkPipeline pipeline_for(VulkanKernel& kernel, uint32_t local_x, uint32_t local_y);

  // vulkan_commands.cpp
  VkCommandBuffer recording();
  void collect_timings(uint32_t queries, std::vector<KernelTiming> dispatches);
  // Copies one dispatch's arguments into the parameter buffers and returns their device address; valid until
  // the recording's submission has finished, after which the space is reused.
  VkDeviceAddress argument_block(const void* bytes, size_t size);

  VkInstance instance_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  VkCommandBuffer cmd_ = VK_NULL_HANDLE;  // the one being recorded, if recording_
  bool recording_ = false;

  // Command buffers submitted and not yet waited for, oldest first, with the memory their commands read.
  struct Submission {
    uint64_t mark = 0;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    std::vector<std::unique_ptr<VulkanArena>> staged, args;
  };
  std::deque<Submission> in_flight_;
  uint64_t last_mark_ = 0;
  std::vector<VkCommandBuffer> spare_cmds_;  // reset, for the next recordings
  std::vector<VkFence> spare_fences_;        // unsignalled

  DeviceInfo info_;
  VkPhysicalDeviceMemoryProperties memory_{};
  uint32_t max_local_size_ = 0;    // work-group items, and x extent
  uint32_t max_local_size_y_ = 0;
  std::unordered_map<std::string, std::unique_ptr<VulkanKernel>> kernels_;
  KernelCache cache_;  // records of the pipelines the driver has compiled before (kernel_cache.h)

  bool profiling_ = false;
  uint32_t timestamp_bits_ = 0;
  float timestamp_period_ = 1.0f;
  VkQueryPool query_pool_ = VK_NULL_HANDLE;
  uint32_t queries_used_ = 0;
  std::vector<KernelTiming> query_dispatches_;  // dispatch of each timestamp pair in the current recording
  std::vector<KernelTiming> timings_;

  // Parameter buffers for kernels whose arguments exceed the push constants: host-visible chunks filled
  // front to back during a recording (the last one up to arg_used_), handed to its submission and back to
  // arg_free_ once it has finished. A few KiB per recording, outside the page pool's budget.
  std::vector<std::unique_ptr<VulkanArena>> arg_chunks_, arg_free_;
  uint64_t arg_used_ = 0;
  // Staging memory of the asynchronous uploads in the current recording; freed when its submission finishes.
  std::vector<std::unique_ptr<VulkanArena>> staged_uploads_;
};

}  // namespace mv::rt::vulkan
