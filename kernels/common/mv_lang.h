/* megavox kernel language shim: lets one header compile as host C++, OpenCL C 1.2 and GLSL 4.60 (Vulkan).
 * Kernel bodies and parameter layouts live in kernels/common and use only what is defined here; the
 * per-language entry points (the .cl and .comp files of each kernel family) stay thin. The PNanoVDB.h pattern.
 *
 * Buffers are typed references: MvBufU32 / MvBufU64 (MvBufF64: doubles, 8-byte aligned), read with
 * MV_LD(buf, i), written with MV_ST(buf, i, v).
 * MV_LD_FAR(buf, i) reads element i of a MvBufU32 at a 64-bit index i, for index arithmetic that passes 2^31.
 * MV_ST_U64(buf, i, v) writes element i of a MvBufU32 viewed as 64-bit words (words 2i and 2i + 1, 8-byte
 * aligned), for an output whose width a parameter picks.
 * MV_LD_PAIR(buf, i) reads 32-bit words i and i + 1 of a MvBufU32 as one 64-bit value (word i low), i of any
 * parity: one load on Vulkan, where lavapipe pays a per-lane loop for each load instruction. MvBufConstU32 is a
 * MvBufU32 only read from (a const pointer on the host, so host code reads const data through the same
 * accessors as the kernels).
 * On Vulkan they are buffer-device-address references (no 128 MiB descriptor limit); on OpenCL global
 * pointers; on the host plain pointers.
 * Indices are 32-bit and stay below 2^31 in every dispatch (Vulkan access chains read them as signed): the host
 * keeps one call of a primitive to MV_MAX_ITEMS items (kMaxDeviceItems in primitives.h).
 * Work-group shared memory, barriers and atomics are in mv_lang_sync.h, included at the end. */
#ifndef MV_LANG_H
#define MV_LANG_H

#if defined(__OPENCL_VERSION__)
#define MV_OPENCL 1
#elif defined(VULKAN) || defined(GL_SPIRV)
#define MV_GLSL 1
#else
#define MV_CPP 1
#endif

/* ---- types, casts, literals, functions ---- */
#if defined(MV_CPP)
#include <cmath>
#include <cstdint>
using std::ceil;
using std::floor;
typedef uint32_t mv_u32;
typedef uint64_t mv_u64;
typedef int32_t mv_i32;
typedef int64_t mv_i64;
typedef float mv_f32;
typedef double mv_f64;
#define MV_INLINE static inline
#define MV_ALWAYS_INLINE static inline __attribute__((always_inline))
#define MV_UNROLL _Pragma("GCC unroll 4")
#define MV_U32(x) ((mv_u32)(x))
#define MV_U64(x) ((mv_u64)(x))
#define MV_I32(x) ((mv_i32)(x))
#define MV_I64(x) ((mv_i64)(x))
#define MV_STRUCT_BEGIN(name) struct name {
#define MV_STRUCT_END(name) };
#define MV_MIN(a, b) ((a) < (b) ? (a) : (b))
#define MV_MAX(a, b) ((a) > (b) ? (a) : (b))
#define MV_F64(x) ((mv_f64)(x))
#define MV_FMIN(a, b) ((a) < (b) ? (a) : (b))
#define MV_FMAX(a, b) ((a) > (b) ? (a) : (b))
#define MV_FABS(x) ((x) < 0.0 ? -(x) : (x))
#elif defined(MV_OPENCL)
#define mv_u32 uint
#define mv_u64 ulong
#define mv_i32 int
#define mv_i64 long
#define mv_f32 float
#define mv_f64 double
#define MV_INLINE static inline
/* for hot helpers PoCL would otherwise call (a call per voxel test costs more than the test) */
#define MV_ALWAYS_INLINE static inline __attribute__((always_inline))
/* a short loop over the axes unrolled, so its arrays live in registers (PoCL keeps a rolled one's on the stack) */
#define MV_UNROLL _Pragma("unroll")
#define MV_U32(x) ((uint)(x))
#define MV_U64(x) ((ulong)(x))
#define MV_I32(x) ((int)(x))
#define MV_I64(x) ((long)(x))
#define MV_STRUCT_BEGIN(name) typedef struct name {
#define MV_STRUCT_END(name) } name;
#define MV_MIN(a, b) min(a, b)
#define MV_MAX(a, b) max(a, b)
#define MV_F64(x) ((double)(x))
/* Compares, as on the host, not fmin/fmax: PoCL adds their NaN handling to every call (the voxelizer ran 20 %
 * slower with them); no kernel feeds them a NaN. */
#define MV_FMIN(a, b) ((a) < (b) ? (a) : (b))
#define MV_FMAX(a, b) ((a) > (b) ? (a) : (b))
#define MV_FABS(x) fabs(x)
#pragma OPENCL FP_CONTRACT OFF
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#else /* GLSL */
#define mv_u32 uint
#define mv_u64 uint64_t
#define mv_i32 int
#define mv_i64 int64_t
#define mv_f32 float
#define mv_f64 double
#define MV_INLINE
#define MV_ALWAYS_INLINE
#define MV_UNROLL
#define MV_U32(x) uint(x)
#define MV_U64(x) uint64_t(x)
#define MV_I32(x) int(x)
#define MV_I64(x) int64_t(x)
#define MV_STRUCT_BEGIN(name) struct name {
#define MV_STRUCT_END(name) };
#define MV_MIN(a, b) min(a, b)
#define MV_MAX(a, b) max(a, b)
#define MV_F64(x) double(x)
#define MV_FMIN(a, b) min(a, b)
#define MV_FMAX(a, b) max(a, b)
#define MV_FABS(x) abs(x)
#endif

/* Exactness: every float expression whose result must match across devices is evaluated as written, without
 * fused multiply-add (OpenCL: FP_CONTRACT OFF above; host: -ffp-contract=off; GLSL: `precise` on the
 * variables that receive it). */
#if defined(MV_GLSL)
#define MV_PRECISE precise
#else
#define MV_PRECISE
#endif

/* ---- layout contracts ----
 * Each struct the host shares with kernels (parameters, records) states its size and field offsets right after
 * its declaration, checked by the host compiler; tests/test_layout.cpp probes each device's view of the same
 * structs (tests/kernels/bodies/layout_probe.h). Fields are 4 bytes and structs 4-aligned: the host packs the
 * parameters right after the buffer addresses (8 bytes each) and GLSL's std430 push constants agree. */
#if defined(MV_CPP)
#include <cstddef>
#define MV_LAYOUT_SIZE(T, bytes) static_assert(sizeof(T) == (bytes) && alignof(T) == 4, #T ": size")
#define MV_LAYOUT_AT(T, field, offset) static_assert(offsetof(T, field) == (offset), #T "." #field ": offset")
#endif

/* ---- bit operations and float bit casts ---- */
#if defined(MV_CPP)
#include <bit>
#define MV_POPCOUNT(x) ((mv_u32)std::popcount((mv_u32)(x)))
#define MV_FIND_MSB(x) (31u - (mv_u32)std::countl_zero((mv_u32)(x))) /* x != 0 */
#define MV_FIND_LSB(x) ((mv_u32)std::countr_zero((mv_u32)(x))) /* x != 0 */
#define MV_FBITS(x) std::bit_cast<mv_u32>((mv_f32)(x))
#define MV_DBITS_HI(x) ((mv_u32)(std::bit_cast<mv_u64>((mv_f64)(x)) >> 32)) /* a double's bits, high word */
#define MV_DBITS_LO(x) ((mv_u32)std::bit_cast<mv_u64>((mv_f64)(x)))
#define MV_BITSF(x) std::bit_cast<mv_f32>((mv_u32)(x))
#define MV_F32(x) ((mv_f32)(x))
#elif defined(MV_OPENCL)
#define MV_POPCOUNT(x) popcount((uint)(x))
#define MV_FIND_MSB(x) (31u - clz((uint)(x)))
#define MV_FIND_LSB(x) (31u - clz((uint)(x) & (0u - (uint)(x)))) /* OpenCL 1.2 has no ctz */
#define MV_FBITS(x) as_uint((float)(x))
#define MV_DBITS_HI(x) ((uint)(as_ulong((double)(x)) >> 32))
#define MV_DBITS_LO(x) ((uint)as_ulong((double)(x)))
#define MV_BITSF(x) as_float((uint)(x))
#define MV_F32(x) ((float)(x))
#else
#define MV_POPCOUNT(x) uint(bitCount(uint(x)))
#define MV_FIND_MSB(x) uint(findMSB(uint(x)))
#define MV_FIND_LSB(x) uint(findLSB(uint(x)))
#define MV_FBITS(x) floatBitsToUint(float(x))
#define MV_DBITS_HI(d_) (unpackDouble2x32(double(d_)).y)
#define MV_DBITS_LO(d_) (unpackDouble2x32(double(d_)).x)
#define MV_BITSF(x) uintBitsToFloat(uint(x))
#define MV_F32(x) float(x)
#endif

/* ---- buffers ---- */
#if defined(MV_CPP)
typedef mv_u32* MvBufU32;
typedef const mv_u32* MvBufConstU32;
typedef mv_u64* MvBufU64;
typedef const float* MvBufF32;
typedef mv_f64* MvBufF64;
#define MV_LD(buf, i) ((buf)[i])
#define MV_ST(buf, i, v) ((buf)[i] = (v))
#elif defined(MV_OPENCL)
#define MvBufU32 __global uint*
#define MvBufConstU32 __global const uint*
#define MvBufU64 __global ulong*
#define MvBufF32 __global float*
#define MvBufF64 __global double*
#define MV_LD(buf, i) ((buf)[i])
#define MV_ST(buf, i, v) ((buf)[i] = (v))
#else
layout(buffer_reference, std430, buffer_reference_align = 4) buffer MvBufU32 { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) buffer MvBufU64 { uint64_t v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer MvBufF32 { float v[]; };
layout(buffer_reference, std430, buffer_reference_align = 8) buffer MvBufF64 { double v[]; };
layout(buffer_reference, std430, buffer_reference_align = 4) buffer MvBufU32Pair { uint64_t v; };
#define MvBufConstU32 MvBufU32
#define MV_LD(buf, i) ((buf).v[i])
#define MV_ST(buf, i, v_) ((buf).v[i] = (v_))
#define MV_LD_PAIR(buf, i) (MvBufU32Pair(uint64_t(buf) + 4ul * uint64_t(i)).v)
#define MV_LD_FAR(buf, i) (MvBufU32(uint64_t(buf) + 4ul * (i)).v[0])
#define MV_ST_U64(buf, i, v_) (MvBufU64(uint64_t(buf)).v[i] = (v_))
#endif
#if !defined(MV_GLSL)
#define MV_LD_PAIR(buf, i) ((mv_u64)(buf)[i] | ((mv_u64)(buf)[(i) + 1] << 32))
#define MV_LD_FAR(buf, i) ((buf)[i])
#endif
#if defined(MV_OPENCL)
#define MV_ST_U64(buf, i, v) (((__global ulong*)(buf))[i] = (v))
#elif defined(MV_CPP)
#define MV_ST_U64(buf, i, v) (((mv_u64*)(buf))[i] = (v))
#endif
/* MV_ST_STREAM(buf, i, v): a store that need not stay in cache (a streaming, non-temporal store where the
 * compiler has one: clang, which PoCL uses; a plain store elsewhere). Whole aligned lines of them write memory
 * without first reading it. MV_STREAM_FENCE() at the end of a kernel that streams orders them before the
 * dispatch's end (x86 streaming stores are weakly ordered). */
#if defined(MV_OPENCL) && defined(__clang__) && defined(__has_builtin)
#if __has_builtin(__builtin_nontemporal_store)
#define MV_ST_STREAM(buf, i, v) __builtin_nontemporal_store((v), &(buf)[i])
#endif
#if (defined(__x86_64__) || defined(__i386__)) && __has_builtin(__builtin_ia32_sfence)
#define MV_STREAM_FENCE() __builtin_ia32_sfence()
#endif
#endif
#if !defined(MV_ST_STREAM)
#define MV_ST_STREAM(buf, i, v) MV_ST(buf, i, v)
#endif
/* MV_PREFETCH(buf, i): a hint that element i of buf will be read soon (a CPU's prefetch, where the compiler has
 * one; nothing elsewhere). For block-per-work-item loops that read at random, which a CPU runs one item at a time. */
#if defined(MV_OPENCL) && defined(__clang__) && defined(__has_builtin)
#if __has_builtin(__builtin_prefetch)
#define MV_PREFETCH(buf, i) __builtin_prefetch(&(buf)[i])
#endif
#elif defined(MV_CPP)
#define MV_PREFETCH(buf, i) __builtin_prefetch(&(buf)[i])
#endif
#if !defined(MV_PREFETCH) && defined(MV_GLSL)
#define MV_PREFETCH(buf, i) /* GLSL has no (void) cast */
#elif !defined(MV_PREFETCH)
#define MV_PREFETCH(buf, i) ((void)0)
#endif
#if !defined(MV_STREAM_FENCE) && defined(MV_GLSL)
#define MV_STREAM_FENCE() /* GLSL has no (void) cast */
#elif !defined(MV_STREAM_FENCE)
#define MV_STREAM_FENCE() ((void)0)
#endif
#define MV_MAX_ITEMS 0x7fffffffu /* items one call of a primitive covers */

/* ---- a private 256-entry array passed to a helper: a pointer in C and OpenCL, an inout array in GLSL ---- */
#if defined(MV_GLSL)
#define MV_ARRAY256_PARAM(type, name) inout type name[256]
#elif defined(MV_OPENCL)
#define MV_ARRAY256_PARAM(type, name) __private type* name
#else
#define MV_ARRAY256_PARAM(type, name) type* name
#endif

/* ---- work-item ids. 1-D dispatches loop grid-stride so group counts stay within limits; 2-D dispatches
 * (image grids) name the dimension d = 0 (x) or 1 (y). ---- */
#if defined(MV_OPENCL)
#define MV_GLOBAL_ID_D(d) MV_U32(get_global_id(d))
#define MV_GLOBAL_SIZE_D(d) MV_U32(get_global_size(d))
#define MV_LOCAL_ID_D(d) MV_U32(get_local_id(d))
#define MV_LOCAL_SIZE_D(d) MV_U32(get_local_size(d))
#define MV_GROUP_ID_D(d) MV_U32(get_group_id(d))
#define MV_NUM_GROUPS_D(d) MV_U32(get_num_groups(d))
#elif defined(MV_GLSL)
#define MV_GLOBAL_ID_D(d) (gl_GlobalInvocationID[d])
#define MV_GLOBAL_SIZE_D(d) (gl_NumWorkGroups[d] * gl_WorkGroupSize[d])
#define MV_LOCAL_ID_D(d) (gl_LocalInvocationID[d])
#define MV_LOCAL_SIZE_D(d) (gl_WorkGroupSize[d])
#define MV_GROUP_ID_D(d) (gl_WorkGroupID[d])
#define MV_NUM_GROUPS_D(d) (gl_NumWorkGroups[d])
#endif
#define MV_GLOBAL_ID() MV_GLOBAL_ID_D(0)
#define MV_GLOBAL_SIZE() MV_GLOBAL_SIZE_D(0)
#define MV_LOCAL_ID() MV_LOCAL_ID_D(0)
#define MV_LOCAL_SIZE() MV_LOCAL_SIZE_D(0)
#define MV_GROUP_ID() MV_GROUP_ID_D(0)
#define MV_NUM_GROUPS() MV_NUM_GROUPS_D(0)

/* The items of [0, n) a work-item takes, step apart: `block` consecutive ones from gid * block (CPU devices, which
 * run each work-item's loop alone, so its neighbouring items share its cache), or with block 0 every gsize-th from
 * gid (grid-stride, GPUs and lavapipe). Loop: for (i = r.begin; i < r.end; i += r.step). */
MV_STRUCT_BEGIN(MvItems)
  mv_u32 begin;
  mv_u32 end;
  mv_u32 step;
MV_STRUCT_END(MvItems)
MV_INLINE MvItems mv_items(mv_u32 block, mv_u32 gid, mv_u32 gsize, mv_u32 n) {
  MvItems r;
  r.begin = block != 0u ? gid * block : gid;
  r.end = block != 0u ? MV_MIN(n, r.begin + block) : n;
  r.step = block != 0u ? 1u : gsize;
  return r;
}

#include "mv_lang_sync.h"

#endif /* MV_LANG_H */
