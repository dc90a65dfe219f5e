// Vulkan backend memory: arenas (a VkBuffer on its own VkDeviceMemory, mapped when the host can see it),
// buffers as ranges of them, and their contents: uploads and downloads (memcpy, or staged in chunks),
// fills and copies recorded in the stream.
#include <vulkan/vulkan.h>

#include <algorithm>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <string>

#include "huge_pages.h"
#include "vulkan_backend.h"
#include "vulkan_device.h"

namespace mv::rt::vulkan {

namespace {

constexpr uint64_t kStagingBytes = 64ull << 20;  // chunk size of staged transfers

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

}  // namespace

std::unique_ptr<BackendArena> VulkanBackend::create_arena(uint64_t bytes) {
  if (bytes == 0 || bytes > info_.max_allocation_bytes)
    fail("cannot allocate an arena of " + std::to_string(bytes) + " bytes (the device allows 1 to " +
         std::to_string(info_.max_allocation_bytes) + " bytes per allocation)");
  constexpr VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                       VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                       VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  // Device-local memory the host can map (CPU devices, ReBAR GPUs) avoids staging copies entirely.
  auto arena = allocate(bytes, usage,
                        {VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                             VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                         VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT});
  auto& a = static_cast<VulkanArena&>(*arena);
  if (info_.type == "cpu" && a.mapped) {
    // A CPU device's memory is host memory the driver allocated (lavapipe: in 4 KiB pages): mark its untouched
    // whole 2 MiB pages for huge pages, and let the pool touch fresh ranges from all cores.
    advise_huge_pages(a.mapped, bytes);
    a.host = a.mapped;
  }
  return arena;
}

// Host-coherent mapped memory of a CPU device: after finish() it holds what the shaders wrote.
const void* VulkanBackend::host_pointer(BackendBuffer& buffer) const {
  auto& b = static_cast<VulkanBuffer&>(buffer);
  return b.arena->host ? static_cast<const char*>(b.arena->host) + b.offset : nullptr;
}

std::unique_ptr<BackendBuffer> VulkanBackend::create_buffer(BackendArena& arena, uint64_t offset, uint64_t bytes) {
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

void VulkanBackend::upload(BackendBuffer& dst, uint64_t offset, const void* src, uint64_t bytes) {
  transfer(as_vk(dst), offset, bytes, src, nullptr);
}

void VulkanBackend::upload_async(BackendBuffer& dst, uint64_t offset, const void* src, uint64_t bytes) {
  VulkanBuffer& b = as_vk(dst);
  check_range(b, offset, bytes, "upload");
  if (bytes == 0) return;
  auto staging = allocate(bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                          {VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT});
  std::memcpy(staging->mapped, src, bytes);
  const VkBufferCopy region{0, b.offset + offset, bytes};
  vkCmdCopyBuffer(recording(), staging->buffer, b.arena->buffer, 1, &region);
  staged_uploads_.push_back(std::move(staging));
}

void VulkanBackend::download(BackendBuffer& src, uint64_t offset, void* dst, uint64_t bytes) {
  transfer(as_vk(src), offset, bytes, nullptr, dst);
}

void VulkanBackend::fill(BackendBuffer& dst, uint64_t offset, uint64_t bytes, uint32_t pattern) {
  VulkanBuffer& b = as_vk(dst);
  check_range(b, offset, bytes, "fill");
  if ((b.offset + offset) % 4 || bytes % 4)
    fail("fill needs offset and size in multiples of 4 bytes (got offset " + std::to_string(b.offset + offset) +
         ", " + std::to_string(bytes) + " bytes)");
  if (bytes == 0) return;
  vkCmdFillBuffer(recording(), b.arena->buffer, b.offset + offset, bytes, pattern);
}

void VulkanBackend::copy(BackendBuffer& src, uint64_t src_offset, BackendBuffer& dst, uint64_t dst_offset,
                         uint64_t bytes) {
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

std::unique_ptr<VulkanArena> VulkanBackend::allocate(uint64_t bytes, VkBufferUsageFlags usage,
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

void VulkanBackend::check_range(const VulkanBuffer& b, uint64_t offset, uint64_t bytes, const char* what) {
  if (offset > b.bytes || bytes > b.bytes - offset)
    fail(std::string(what) + " of " + std::to_string(bytes) + " bytes at offset " + std::to_string(offset) +
         " overruns a buffer of " + std::to_string(b.bytes) + " bytes");
}

void VulkanBackend::transfer(VulkanBuffer& b, uint64_t offset, uint64_t bytes, const void* from_host, void* to_host) {
  check_range(b, offset, bytes, from_host ? "upload" : "download");
  if (bytes == 0) return;
  Blocking blocked(*this);
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

}  // namespace mv::rt::vulkan
