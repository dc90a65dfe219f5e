# Embeds kernel lists (kernels/kernels.cmake for the library, tests/kernels/kernels.cmake for the tests):
#  - each OpenCL program (.cl) with its #include "..." lines inlined, as a C++ raw string;
#  - each GLSL entry compiled to SPIR-V by glslangValidator (target Vulkan 1.2) as a uint32_t array;
#  - a table (kernel_table.cpp) mapping kernels to both and to their declared signature;
#  - the enum host code names the list's kernels by (KernelId in megavox/kernel_ids.h for the library).
# A list's .cl and .comp paths are relative to its folder (kernels/ or tests/kernels/); their #include lines
# resolve against the including file's folder, then kernels/ (every list shares kernels/common).
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)


function(mv_cl_program cl)
  string(MAKE_C_IDENTIFIER ${cl} id)
  set(out ${MV_KERNEL_GEN}/cl_${id}.h)
  if(NOT cl IN_LIST MV_CL_PROGRAMS)
    add_custom_command(OUTPUT ${out}
      COMMAND ${CMAKE_COMMAND} -DIN=${MV_KERNEL_SRC}/${cl} -DROOT=${MV_KERNEL_DIR} -DOUT=${out} -DVAR=mv_cl_${id}
              -P ${CMAKE_SOURCE_DIR}/cmake/inline_cl.cmake
      DEPENDS ${MV_KERNEL_SRC}/${cl} ${MV_KERNEL_COMMON} ${MV_KERNEL_OWN} ${CMAKE_SOURCE_DIR}/cmake/inline_cl.cmake
      COMMENT "Embedding OpenCL program ${cl}")
    list(APPEND MV_CL_PROGRAMS ${cl})
    set(MV_CL_PROGRAMS ${MV_CL_PROGRAMS} PARENT_SCOPE)
    list(APPEND MV_KERNEL_SOURCES ${out})
    set(MV_KERNEL_SOURCES ${MV_KERNEL_SOURCES} PARENT_SCOPE)
    string(APPEND MV_KERNEL_INCLUDES "#include \"cl_${id}.h\"\n")
    set(MV_KERNEL_INCLUDES ${MV_KERNEL_INCLUDES} PARENT_SCOPE)
  endif()
endfunction()

# The header that defines a parameter struct (MV_STRUCT_BEGIN(name)), in kernels/common or the list's own
# folder: the kernel table includes it (by its path from kernels/ or from that folder) to record the struct's
# type and size, which every dispatch is checked against.
function(mv_params_header params out_var)
  foreach(h ${MV_KERNEL_COMMON} ${MV_KERNEL_OWN})
    file(STRINGS ${h} hit REGEX "MV_STRUCT_BEGIN\\(${params}\\)")
    if(hit)
      if(h IN_LIST MV_KERNEL_COMMON)
        file(RELATIVE_PATH rel ${MV_KERNEL_DIR} ${h})
      else()
        file(RELATIVE_PATH rel ${MV_KERNEL_SRC} ${h})
      endif()
      set(${out_var} ${rel} PARENT_SCOPE)
      return()
    endif()
  endforeach()
  message(FATAL_ERROR "${MV_KERNEL_LIST}: no header of kernels/common or of its folder defines the parameter struct ${params}")
endfunction()

# mv_kernel(name program.cl entry.comp buffers params [GLSL defines...]), one line per kernel of a list;
# MV_ARGS_BUFFER among the defines makes Vulkan pass the arguments through a parameter buffer instead of push
# constants (mv_glsl_prelude.h); NEEDS_<FEATURE> (not passed to glslang) names a device feature the kernel needs
# (kernel_table.h).
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
            -o ${_spv} ${MV_KERNEL_SRC}/${comp}
    DEPENDS ${MV_KERNEL_SRC}/${comp} ${MV_KERNEL_COMMON} ${MV_KERNEL_OWN}
    COMMENT "Compiling ${comp} (${name}) to SPIR-V")
  list(APPEND MV_KERNEL_SOURCES ${_spv})
  string(APPEND MV_KERNEL_INCLUDES "#include \"spv_${name}.h\"\n")
  string(APPEND MV_KERNEL_ENTRIES
    "  {\"${name}\", \"${cl}\", mv_cl_${_cl_id}, mv_spv_${name}, sizeof(mv_spv_${name}) / sizeof(uint32_t),\n"
    "   {${buffers}, &typeid(${params}), sizeof(${params}), \"${params}\", ${_args_in_buffer}, ${_needs}}},\n")
  string(APPEND MV_KERNEL_IDS "  ${name},\n")
  math(EXPR MV_KERNEL_COUNT "${MV_KERNEL_COUNT} + 1")
endmacro()

# Embeds the kernels a list names into GEN (a folder of its own per list): writes GEN/kernel_table.cpp, whose
# FIND(ENUM id) returns a kernel's table entry (nullptr out of range), and GEN/IDS, the enum `ENUM` with COUNT
# kernels, whose comment shows a dispatch as DISPATCH; sets OUT to the generated sources.
function(mv_embed_kernels list)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "GEN;ENUM;COUNT;FIND;IDS;DISPATCH;OUT" "")
  # Set here, not at the top: a list may be embedded from another folder, whose variables are its own.
  set(MV_KERNEL_DIR ${CMAKE_SOURCE_DIR}/kernels)
  file(GLOB MV_KERNEL_COMMON CONFIGURE_DEPENDS ${MV_KERNEL_DIR}/common/*.h)
  set(MV_KERNEL_LIST ${list})
  get_filename_component(MV_KERNEL_SRC ${list} DIRECTORY)
  # Headers of the list's own folder (kernel bodies only its kernels use) other than kernels/common's.
  set(MV_KERNEL_OWN "")
  if(NOT MV_KERNEL_SRC STREQUAL MV_KERNEL_DIR)
    file(GLOB_RECURSE MV_KERNEL_OWN CONFIGURE_DEPENDS ${MV_KERNEL_SRC}/*.h)
  endif()
  set(MV_KERNEL_GEN ${arg_GEN})
  file(MAKE_DIRECTORY ${MV_KERNEL_GEN})
  set(MV_KERNEL_SOURCES "")
  set(MV_KERNEL_INCLUDES "")
  set(MV_KERNEL_ENTRIES "")
  set(MV_CL_PROGRAMS "")
  set(MV_PARAMS_HEADERS "")
  set(MV_KERNEL_IDS "")
  set(MV_KERNEL_COUNT 0)
  set(MV_KERNEL_ENUM ${arg_ENUM})
  set(MV_KERNEL_COUNT_NAME ${arg_COUNT})
  set(MV_KERNEL_FIND ${arg_FIND})
  set(MV_KERNEL_IDS_HEADER ${arg_IDS})
  set(MV_KERNEL_DISPATCH "${arg_DISPATCH}")
  file(RELATIVE_PATH MV_KERNEL_LIST_NAME ${CMAKE_SOURCE_DIR} ${list})
  include(${list})
  configure_file(${CMAKE_SOURCE_DIR}/cmake/kernel_table.cpp.in ${MV_KERNEL_GEN}/kernel_table.cpp @ONLY)
  configure_file(${CMAKE_SOURCE_DIR}/cmake/kernel_ids.h.in ${MV_KERNEL_GEN}/${arg_IDS} @ONLY)
  list(APPEND MV_KERNEL_SOURCES ${MV_KERNEL_GEN}/kernel_table.cpp)
  set(${arg_OUT} ${MV_KERNEL_SOURCES} PARENT_SCOPE)
endfunction()

# The library's kernels.
set(MV_KERNEL_GEN ${CMAKE_BINARY_DIR}/kernels_gen)
mv_embed_kernels(${CMAKE_SOURCE_DIR}/kernels/kernels.cmake GEN ${MV_KERNEL_GEN} ENUM KernelId COUNT kKernelCount
                 FIND find_embedded_kernel IDS public/megavox/kernel_ids.h DISPATCH "Device::kernel(KernelId::scan_reduce)"
                 OUT MV_KERNEL_SOURCES)
