// Vulkan backend commands: the command buffer recorded lazily (dispatches with their push constants, barriers),
// submitted with a fence by submit() and waited for by wait() (finish() does both), and the timestamp queries
// that time profiled dispatches.
#include <vulkan/vulkan.h>

#include <array>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "vulkan_backend.h"
#include "vulkan_device.h"

namespace mv::rt::vulkan {

namespace {

constexpr uint32_t kTimestampQueries = 8192;                      // two per profiled dispatch
constexpr uint64_t kFenceTimeoutNs = 30ull * 60 * 1000000000ull;  // 30 minutes
constexpr VkPipelineStageFlags kWorkStages = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;

}  // namespace

VkCommandBuffer VulkanBackend::recording() {
  if (!recording_) {
    if (!cmd_ && !spare_cmds_.empty()) {
      cmd_ = spare_cmds_.back();
      spare_cmds_.pop_back();
    }
    if (!cmd_) {
      auto ai = vk<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
      ai.commandPool = pool_;
      ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
      ai.commandBufferCount = 1;
      check(vkAllocateCommandBuffers(device_, &ai, &cmd_), "vkAllocateCommandBuffers");
    }
    auto bi = vk<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(cmd_, &bi), "vkBeginCommandBuffer");
    recording_ = true;
  }
  return cmd_;
}

void VulkanBackend::dispatch(BackendKernel& k, const LaunchGrid& grid, std::span<BackendBuffer* const> buffers,
                             const void* params, size_t params_bytes) {
  auto& kernel = static_cast<VulkanKernel&>(k);
  if (grid.groups[0] == 0 || grid.groups[1] == 0) return;
  if (grid.groups[0] > info_.max_groups || grid.groups[1] > info_.max_groups_y)
    fail("kernel '" + kernel.name + "': " + std::to_string(grid.groups[0]) + "x" + std::to_string(grid.groups[1]) +
         " groups exceed the device limit of " + std::to_string(info_.max_groups) + "x" +
         std::to_string(info_.max_groups_y));
  // The arguments, laid out as the shader's Args block (std430): buffer addresses, then the parameters.
  const size_t arg_bytes = 8 * buffers.size() + params_bytes;
  if (arg_bytes > kMaxArgBytes)
    fail("kernel '" + kernel.name + "': " + std::to_string(arg_bytes) + " argument bytes exceed " +
         std::to_string(kMaxArgBytes));
  if (arg_bytes > kMaxPushBytes && !kernel.args_in_buffer)
    fail("kernel '" + kernel.name + "': " + std::to_string(buffers.size()) + " buffers and " +
         std::to_string(params_bytes) + " parameter bytes exceed the " + std::to_string(kMaxPushBytes) +
         "-byte push-constant limit (declare it with MV_ARGS_BUFFER in kernels/kernels.cmake)");
  std::array<unsigned char, kMaxArgBytes> args{};
  for (size_t i = 0; i < buffers.size(); ++i) {
    // A null (empty) buffer passes address 0, as OpenCL passes a null cl_mem: the kernel must not touch it.
    const VkDeviceAddress address = buffers[i] ? as_vk(*buffers[i]).address : 0;
    std::memcpy(args.data() + 8 * i, &address, sizeof(address));
  }
  if (params_bytes) std::memcpy(args.data() + 8 * buffers.size(), params, params_bytes);
  const bool timed = profiling_;
  if (timed && queries_used_ + 2 > kTimestampQueries) finish();  // before the parameter buffers are written:
                                                                  // finish() hands their space out again
  size_t push_bytes = arg_bytes;
  if (kernel.args_in_buffer) {  // push only the address of a copy in a parameter buffer
    const VkDeviceAddress block = argument_block(args.data(), arg_bytes);
    std::memcpy(args.data(), &block, sizeof(block));
    push_bytes = sizeof(block);
  }

  const VkPipeline pipeline = pipeline_for(kernel, grid.local[0], grid.local[1]);
  const VkCommandBuffer cmd = recording();
  if (timed) {
    if (queries_used_ == 0) vkCmdResetQueryPool(cmd, query_pool_, 0, kTimestampQueries);
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, query_pool_, queries_used_++);
  }
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
  if (push_bytes)  // Vulkan wants a multiple of 4; the padding is zero and still within kMaxPushBytes
    vkCmdPushConstants(cmd, kernel.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0,
                       static_cast<uint32_t>((push_bytes + 3) & ~size_t{3}), args.data());
  vkCmdDispatch(cmd, grid.groups[0], grid.groups[1], 1);
  if (timed) {
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, query_pool_, queries_used_++);
    query_dispatches_.push_back({kernel.name, 0, uint64_t{grid.groups[0]} * grid.local[0] * grid.groups[1] * grid.local[1]});
  }
}

VkDeviceAddress VulkanBackend::argument_block(const void* bytes, size_t size) {
  constexpr uint64_t kChunkBytes = 64 << 10;
  const uint64_t need = (size + 15) & ~uint64_t{15};  // 16-byte aligned blocks (std430 alignment of any field)
  if (arg_chunks_.empty() || arg_used_ + need > arg_chunks_.back()->bytes) {
    if (!arg_free_.empty()) {
      arg_chunks_.push_back(std::move(arg_free_.back()));
      arg_free_.pop_back();
    } else {
      arg_chunks_.push_back(allocate(kChunkBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                                      VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                                     {VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                          VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                                      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT}));
      if (!arg_chunks_.back()->mapped) fail("no host-visible memory for kernel parameter buffers on " + info_.name);
    }
    arg_used_ = 0;
  }
  VulkanArena& chunk = *arg_chunks_.back();
  std::memcpy(static_cast<unsigned char*>(chunk.mapped) + arg_used_, bytes, size);
  const VkDeviceAddress address = chunk.address + arg_used_;
  arg_used_ += need;
  return address;
}

void VulkanBackend::barrier() {
  auto mb = vk<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                     VK_ACCESS_TRANSFER_WRITE_BIT;
  vkCmdPipelineBarrier(recording(), kWorkStages, kWorkStages, 0, 1, &mb, 0, nullptr, 0, nullptr);
}

uint64_t VulkanBackend::submit() {
  if (!recording_) return last_mark_;  // nothing recorded since: the last mark covers everything
  // A fence wait alone does not make device writes visible to the host; this barrier does.
  auto to_host = vk<VkMemoryBarrier>(VK_STRUCTURE_TYPE_MEMORY_BARRIER);
  to_host.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd_, kWorkStages, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &to_host, 0, nullptr, 0, nullptr);
  recording_ = false;  // a failed end or submission leaves cmd_ to be begun (and so reset) again
  check(vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");

  Submission sub;
  if (spare_fences_.empty()) {
    auto fi = vk<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
    check(vkCreateFence(device_, &fi, nullptr, &sub.fence), "vkCreateFence");
  } else {
    sub.fence = spare_fences_.back();
    spare_fences_.pop_back();
  }
  auto si = vk<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd_;
  const VkResult submitted = vkQueueSubmit(queue_, 1, &si, sub.fence);
  if (submitted != VK_SUCCESS) spare_fences_.push_back(sub.fence);
  check(submitted, "vkQueueSubmit");
  sub.mark = ++last_mark_;
  sub.cmd = std::exchange(cmd_, VK_NULL_HANDLE);
  sub.staged = std::exchange(staged_uploads_, {});
  sub.args = std::exchange(arg_chunks_, {});
  arg_used_ = 0;
  in_flight_.push_back(std::move(sub));
  return last_mark_;
}

void VulkanBackend::wait(uint64_t mark) {
  if (mark > last_mark_) fail("wait for stream mark " + std::to_string(mark) + ", which was never made");
  Blocking blocked(*this);
  while (!in_flight_.empty() && in_flight_.front().mark <= mark) {
    Submission& sub = in_flight_.front();
    const VkResult waited = vkWaitForFences(device_, 1, &sub.fence, VK_TRUE, kFenceTimeoutNs);
    if (waited == VK_TIMEOUT) fail("device work did not finish within 30 minutes on " + info_.name);
    check(waited, "vkWaitForFences");
    check(vkResetFences(device_, 1, &sub.fence), "vkResetFences");
    check(vkResetCommandBuffer(sub.cmd, 0), "vkResetCommandBuffer");
    spare_fences_.push_back(sub.fence);
    spare_cmds_.push_back(sub.cmd);
    for (auto& chunk : sub.args) arg_free_.push_back(std::move(chunk));  // the work that read them is done
    in_flight_.pop_front();                                                // frees its staging memory
  }
  // Timestamps are read once no recorded work is left: the queries of one recording may span submissions.
  if (in_flight_.empty() && !recording_ && queries_used_) {
    const uint32_t queries = std::exchange(queries_used_, 0);
    collect_timings(queries, std::exchange(query_dispatches_, {}));
  }
}

void VulkanBackend::set_profiling(bool on) {
  profiling_ = on && timestamp_bits_ > 0;  // a queue family without timestamps yields no timings
  if (profiling_ && !query_pool_) {
    auto qi = vk<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
    qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qi.queryCount = kTimestampQueries;
    check(vkCreateQueryPool(device_, &qi, nullptr, &query_pool_), "vkCreateQueryPool");
  }
}

void VulkanBackend::collect_timings(uint32_t queries, std::vector<KernelTiming> dispatches) {
  std::vector<uint64_t> ticks(queries);
  check(vkGetQueryPoolResults(device_, query_pool_, 0, queries, ticks.size() * sizeof(uint64_t), ticks.data(),
                              sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
        "vkGetQueryPoolResults");
  const uint64_t mask = timestamp_bits_ >= 64 ? ~uint64_t{0} : (uint64_t{1} << timestamp_bits_) - 1;
  for (size_t i = 0; i < dispatches.size(); ++i) {
    const uint64_t delta = (ticks[2 * i + 1] - ticks[2 * i]) & mask;  // the mask absorbs counter wrap-around
    dispatches[i].ns = static_cast<uint64_t>(static_cast<double>(delta) * timestamp_period_);
    timings_.push_back(std::move(dispatches[i]));
  }
}

}  // namespace mv::rt::vulkan
