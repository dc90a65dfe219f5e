// Vulkan backend kernels: a shader module and pipeline layout per kernel, checked when the kernel is asked
// for, and one compute pipeline per local size (specialization constant 0), made at first dispatch.
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

VkPipeline VulkanBackend::pipeline_for(VulkanKernel& kernel, uint32_t local_size) {
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

}  // namespace mv::rt::vulkan
