// Kernels embedded at build time (generated table; see cmake/EmbedKernels.cmake and kernels/kernels.cmake).
#pragma once
#include <cstddef>
#include <cstdint>
#include <typeinfo>

#include "megavox/kernel_ids.h"

namespace mv::rt {

// What a kernel takes, as kernels/kernels.cmake declares it; Device checks every dispatch against it.
struct KernelSignature {
  uint32_t buffers = 0;                     // buffer arguments, in order, before the parameters
  const std::type_info* params = nullptr;   // the parameter struct (kernels/common); nullptr = unchecked
  size_t params_bytes = 0;
  const char* params_name = "";
  bool args_in_buffer = false;              // Vulkan: arguments through a parameter buffer (MV_ARGS_BUFFER)
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
