/* Extensions every megavox compute shader needs; included by each .comp entry point right after
 * "#extension GL_GOOGLE_include_directive : require". The work-group size is specialization constants 0 (x)
 * and 1 (y, 1 unless a 2-D dispatch asks), chosen by the host per device. 64-bit atomics need the device's
 * shaderBufferInt64Atomics / shaderSharedInt64Atomics, which the backend enables where present. */
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_shader_atomic_int64 : require
layout(local_size_x_id = 0, local_size_y_id = 1) in;

/* The entry's arguments (buffers, then the parameter struct) as one block `args`: MV_ARGS(fields) declares
 * them as push constants (128 bytes at most), or, for a kernel compiled with MV_ARGS_BUFFER (kernels.cmake),
 * in a parameter buffer whose address is the one push constant. The same bytes either way (std430). */
#if defined(MV_ARGS_BUFFER)
#define MV_ARGS(fields) \
  layout(buffer_reference, std430, buffer_reference_align = 16) buffer MvArgsBlock { fields }; \
  layout(push_constant) uniform MvArgsPush { MvArgsBlock block; } mv_push
#define args mv_push.block
#else
#define MV_ARGS(fields) layout(push_constant) uniform Args { fields } args
#endif
