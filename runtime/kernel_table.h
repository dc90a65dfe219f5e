// Kernels embedded at build time (generated table; see cmake/EmbedKernels.cmake and kernels/kernels.cmake).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <typeinfo>

#include "megavox/device.h"

namespace mv::rt {

// Device features beyond the base every kernel uses, as NEEDS_<NAME> in kernels/kernels.cmake.
enum KernelNeeds : uint32_t {
  kNeedsATOMICS64 = 1u << 0,         // DeviceInfo::atomics64
  kNeedsSHARED_ATOMICS64 = 1u << 1,  // DeviceInfo::shared_atomics64
};

// Empty when the device has every feature in `needs`, else what it lacks, e.g. "64-bit atomics on global memory".
std::string missing_features(const DeviceInfo& info, uint32_t needs);

// What a kernel takes, as kernels/kernels.cmake declares it; Device checks every dispatch against it.
struct KernelSignature {
  uint32_t buffers = 0;                     // buffer arguments, in order, before the parameters
  const std::type_info* params = nullptr;   // the parameter struct (kernels/common); nullptr = unchecked
  size_t params_bytes = 0;
  const char* params_name = "";
  bool args_in_buffer = false;              // Vulkan: arguments through a parameter buffer (MV_ARGS_BUFFER)
  uint32_t needs = 0;                       // KernelNeeds
};

struct EmbeddedKernel {
  const char* name;        // entry name in the OpenCL program; GLSL modules use "main"
  const char* cl_program;  // path of the .cl under kernels/, the key of the built-program cache
  const char* cl_source;   // with includes inlined
  const uint32_t* spirv;
  size_t spirv_words;
  KernelSignature signature;
};

const EmbeddedKernel* find_embedded_kernel(KernelId id);  // nullptr when out of range

}  // namespace mv::rt
