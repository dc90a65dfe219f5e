// Kernels embedded at build time (generated table; see cmake/EmbedKernels.cmake and kernels/kernels.cmake).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace mv::rt {

struct EmbeddedKernel {
  const char* name;        // entry name in the OpenCL program; GLSL modules use "main"
  const char* cl_program;  // path of the .cl under kernels/, the key of the built-program cache
  const char* cl_source;   // with includes inlined
  const uint32_t* spirv;
  size_t spirv_words;
};

const EmbeddedKernel* find_embedded_kernel(std::string_view name);  // nullptr when unknown

}  // namespace mv::rt
