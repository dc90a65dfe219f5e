/* Extensions every megavox compute shader needs; included by each .comp entry point right after
 * "#extension GL_GOOGLE_include_directive : require". The local
 * size is specialization constant 0, chosen by the host per device. */
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
layout(local_size_x_id = 0) in;
