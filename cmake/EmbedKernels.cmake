# Embeds the kernels listed in kernels/kernels.cmake into the library:
#  - each OpenCL program (.cl) with its #include "..." lines inlined, as a C++ raw string;
#  - each GLSL entry compiled to SPIR-V by glslangValidator (target Vulkan 1.2) as a uint32_t array;
#  - a table (kernel_table.cpp) mapping kernels to both and to their declared signature;
#  - the KernelId enum (megavox/kernel_ids.h) host code names kernels by.
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)

set(MV_KERNEL_DIR ${CMAKE_SOURCE_DIR}/kernels)
set(MV_KERNEL_GEN ${CMAKE_BINARY_DIR}/kernels_gen)
file(MAKE_DIRECTORY ${MV_KERNEL_GEN})
file(GLOB MV_KERNEL_COMMON CONFIGURE_DEPENDS ${MV_KERNEL_DIR}/common/*.h)

set(MV_KERNEL_SOURCES "")
set(MV_KERNEL_INCLUDES "")
set(MV_KERNEL_ENTRIES "")
set(MV_CL_PROGRAMS "")
set(MV_PARAMS_HEADERS "")
set(MV_KERNEL_IDS "")
set(MV_KERNEL_COUNT 0)

function(mv_cl_program cl)
  string(MAKE_C_IDENTIFIER ${cl} id)
  set(out ${MV_KERNEL_GEN}/cl_${id}.h)
  if(NOT cl IN_LIST MV_CL_PROGRAMS)
    add_custom_command(OUTPUT ${out}
      COMMAND ${CMAKE_COMMAND} -DIN=${MV_KERNEL_DIR}/${cl} -DROOT=${MV_KERNEL_DIR} -DOUT=${out} -DVAR=mv_cl_${id}
              -P ${CMAKE_SOURCE_DIR}/cmake/inline_cl.cmake
      DEPENDS ${MV_KERNEL_DIR}/${cl} ${MV_KERNEL_COMMON} ${CMAKE_SOURCE_DIR}/cmake/inline_cl.cmake
      COMMENT "Embedding OpenCL program ${cl}")
    list(APPEND MV_CL_PROGRAMS ${cl})
    set(MV_CL_PROGRAMS ${MV_CL_PROGRAMS} PARENT_SCOPE)
    list(APPEND MV_KERNEL_SOURCES ${out})
    set(MV_KERNEL_SOURCES ${MV_KERNEL_SOURCES} PARENT_SCOPE)
    string(APPEND MV_KERNEL_INCLUDES "#include \"cl_${id}.h\"\n")
    set(MV_KERNEL_INCLUDES ${MV_KERNEL_INCLUDES} PARENT_SCOPE)
  endif()
endfunction()

# The header of kernels/common that defines a parameter struct (MV_STRUCT_BEGIN(name)): the kernel table
# includes it to record the struct's type and size, which every dispatch is checked against.
function(mv_params_header params out_var)
  foreach(h ${MV_KERNEL_COMMON})
    file(STRINGS ${h} hit REGEX "MV_STRUCT_BEGIN\\(${params}\\)")
    if(hit)
      file(RELATIVE_PATH rel ${MV_KERNEL_DIR} ${h})
      set(${out_var} ${rel} PARENT_SCOPE)
      return()
    endif()
  endforeach()
  message(FATAL_ERROR "kernels/kernels.cmake: no kernels/common header defines the parameter struct ${params}")
endfunction()

# mv_kernel(name program.cl entry.comp buffers params [GLSL defines...]); MV_ARGS_BUFFER among the defines
# makes Vulkan pass the arguments through a parameter buffer instead of push constants (mv_glsl_prelude.h);
# NEEDS_<FEATURE> (not passed to glslang) names a device feature the kernel needs (kernel_table.h).
macro(mv_kernel name cl comp buffers params)
  mv_cl_program(${cl})
  string(MAKE_C_IDENTIFIER ${cl} _cl_id)
  set(_defs "")
  set(_args_in_buffer false)
  set(_needs "0")
  foreach(d ${ARGN})
    if(d MATCHES "^NEEDS_(.*)$")  # a device feature the kernel's family needs (KernelNeeds in kernel_table.h)
      string(APPEND _needs " | kNeeds${CMAKE_MATCH_1}")
      continue()
    endif()
    list(APPEND _defs -D${d})
    if(d STREQUAL "MV_ARGS_BUFFER")
      set(_args_in_buffer true)
    endif()
  endforeach()
  mv_params_header(${params} _params_h)
  if(NOT _params_h IN_LIST MV_PARAMS_HEADERS)
    list(APPEND MV_PARAMS_HEADERS ${_params_h})
    string(APPEND MV_KERNEL_INCLUDES "#include \"${_params_h}\"\n")
  endif()
  set(_spv ${MV_KERNEL_GEN}/spv_${name}.h)
  add_custom_command(OUTPUT ${_spv}
    COMMAND ${GLSLANG_VALIDATOR} -V --target-env vulkan1.2 -I${MV_KERNEL_DIR} ${_defs} --vn mv_spv_${name}
            -o ${_spv} ${MV_KERNEL_DIR}/${comp}
    DEPENDS ${MV_KERNEL_DIR}/${comp} ${MV_KERNEL_COMMON}
    COMMENT "Compiling ${comp} (${name}) to SPIR-V")
  list(APPEND MV_KERNEL_SOURCES ${_spv})
  string(APPEND MV_KERNEL_INCLUDES "#include \"spv_${name}.h\"\n")
  string(APPEND MV_KERNEL_ENTRIES
    "  {\"${name}\", \"${cl}\", mv_cl_${_cl_id}, mv_spv_${name}, sizeof(mv_spv_${name}) / sizeof(uint32_t),\n"
    "   {${buffers}, &typeid(${params}), sizeof(${params}), \"${params}\", ${_args_in_buffer}, ${_needs}}},\n")
  string(APPEND MV_KERNEL_IDS "  ${name},\n")
  math(EXPR MV_KERNEL_COUNT "${MV_KERNEL_COUNT} + 1")
endmacro()

include(${MV_KERNEL_DIR}/kernels.cmake)

configure_file(${CMAKE_SOURCE_DIR}/cmake/kernel_table.cpp.in ${MV_KERNEL_GEN}/kernel_table.cpp @ONLY)
configure_file(${CMAKE_SOURCE_DIR}/cmake/kernel_ids.h.in ${MV_KERNEL_GEN}/public/megavox/kernel_ids.h @ONLY)
list(APPEND MV_KERNEL_SOURCES ${MV_KERNEL_GEN}/kernel_table.cpp)
