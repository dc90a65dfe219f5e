// Vulkan backend kernels: a shader module and pipeline layout per kernel, checked when the kernel is asked
// for, and one compute pipeline per work-group size (specialization constants 0 and 1), made at first dispatch.
// Making a pipeline compiles the module in the driver (lavapipe: through LLVM, minutes for a build's kernels),
// unless the driver's own cache holds it: a pipeline made before on this device and driver is recorded in the
// kernel cache, and one without a record is announced (Backend::on_compile). A driver cache emptied by hand
// behind the records compiles unannounced.
#include <vulkan/vulkan.h>

#include <cstdio>
#include <memory>
#include <string>

#include "vulkan_backend.h"
#include "vulkan_device.h"

namespace mv::rt::vulkan {

BackendKernel& VulkanBackend::kernel(const KernelDesc& desc) {
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
  k->args_in_buffer = desc.args_in_buffer;
  k->cache_key = KernelCache::key({std::string_view(reinterpret_cast<const char*>(desc.spirv), desc.spirv_words * 4),
                                   info_.name, info_.driver, info_.api_version});
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

VkPipeline VulkanBackend::pipeline_for(VulkanKernel& kernel, uint32_t local_x, uint32_t local_y) {
  const uint64_t key = local_x | uint64_t{local_y} << 32;
  if (auto it = kernel.pipelines.find(key); it != kernel.pipelines.end()) return it->second;
  if (local_x == 0 || local_x > max_local_size_ || local_y == 0 || local_y > max_local_size_y_ ||
      uint64_t{local_x} * local_y > max_local_size_)
    fail("kernel '" + kernel.name + "': work-group size " + std::to_string(local_x) + "x" + std::to_string(local_y) +
         " is outside the device's (x up to " + std::to_string(max_local_size_) + ", y up to " +
         std::to_string(max_local_size_y_) + ", " + std::to_string(max_local_size_) + " items)");
  // constant_id 0 = local_size_x, 1 = local_size_y (mv_glsl_prelude.h)
  const uint32_t sizes[2] = {local_x, local_y};
  const VkSpecializationMapEntry entries[2] = {{0, 0, sizeof(uint32_t)}, {1, sizeof(uint32_t), sizeof(uint32_t)}};
  const VkSpecializationInfo spec{2, entries, sizeof(sizes), sizes};
  auto ci = vk<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
  ci.stage = vk<VkPipelineShaderStageCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO);
  ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  ci.stage.module = kernel.module;
  ci.stage.pName = "main";
  ci.stage.pSpecializationInfo = &spec;
  ci.layout = kernel.layout;
  VkPipeline pipeline = VK_NULL_HANDLE;
  const std::string size = std::to_string(local_x) + "x" + std::to_string(local_y);
  auto create = [&] {
    check(vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &ci, nullptr, &pipeline),
          "kernel '" + kernel.name + "': vkCreateComputePipelines for work-group size " + size);
  };
  const std::string record = KernelCache::key({kernel.cache_key, size});
  if (cache_.contains(record)) {
    create();
  } else {
    announced_compile(kernel.name + " (" + size + ")", create);
    cache_.store(record, "made before; the driver's cache holds its code\n");
  }
  kernel.pipelines.emplace(key, pipeline);
  return pipeline;
}

}  // namespace mv::rt::vulkan
