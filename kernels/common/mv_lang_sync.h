/* The kernel language shim's synchronisation (mv_lang.h): work-group shared memory, barriers and atomics on
 * buffers and shared arrays, for OpenCL C, GLSL and host C++. Part of mv_lang.h, which includes it last: it
 * uses the language picked and the types defined there, so include mv_lang.h, not this file. */
#ifndef MV_LANG_SYNC_H
#define MV_LANG_SYNC_H

/* ---- work-group shared memory and barriers ----
 * MV_SHARED(type, name, count) declares a shared array in an entry point: inside the kernel function in a .cl
 * (OpenCL C 1.2 allows __local only at kernel scope), at global scope in a .comp (GLSL allows `shared` only
 * there). Bodies in kernels/common reach it by the same name: they take MV_SHARED_PARAM(type, name) as a
 * leading parameter and are called with MV_SHARED_ARG(name) (each expands with its trailing comma: a pointer
 * in OpenCL and C++, nothing in GLSL, where the body sees the global array itself). GLSL resolves that name
 * where the body is written, so such a body lives in a header of its own, which a .comp includes after
 * declaring the array (tests/kernels/bodies/lang_histogram.h is the smallest example).
 * MV_BARRIER(): every work-item of the group waits, and shared and global writes before it are visible after
 * it. Only in uniform control flow (every item of the group reaches the same barriers). */
#if defined(MV_OPENCL)
#define MV_SHARED(type, name, count) __local type name[count]
#define MV_SHARED_PARAM(type, name) __local type* name,
#define MV_SHARED_ARG(name) name,
#define MV_BARRIER() barrier(CLK_LOCAL_MEM_FENCE | CLK_GLOBAL_MEM_FENCE)
#elif defined(MV_GLSL)
#define MV_SHARED(type, name, count) shared type name[count]
#define MV_SHARED_PARAM(type, name)
#define MV_SHARED_ARG(name)
#define MV_BARRIER() \
  memoryBarrierShared(); \
  memoryBarrierBuffer(); \
  barrier()
#else /* host C++ runs a group's work-items one after another: a barrier has nothing to wait for */
#define MV_SHARED(type, name, count) type name[count]
#define MV_SHARED_PARAM(type, name) type* name,
#define MV_SHARED_ARG(name) name,
#define MV_BARRIER() ((void)0)
#endif

/* ---- atomics, 32- or 64-bit by the element type, on a buffer element (MV_ATOMIC_*(buf, i, ...)) or a
 * shared-array element (MV_SHARED_ATOMIC_*(arr, i, ...)). Each returns the value before the operation;
 * CAS stores v only where the element equals cmp. 64-bit needs DeviceInfo::atomics64 (global) and
 * shared_atomics64 (shared): kernels that use them declare NEEDS_ATOMICS64 / NEEDS_SHARED_ATOMICS64 in
 * kernels/kernels.cmake. (GLSL macro parameters are never named v: buffers' member is .v.) ---- */
#if defined(MV_OPENCL)
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#pragma OPENCL EXTENSION cl_khr_int64_extended_atomics : enable
#define MV_ATOMIC_ADD(buf, i, v) atom_add(&(buf)[i], v)
#define MV_ATOMIC_MIN(buf, i, v) atom_min(&(buf)[i], v)
#define MV_ATOMIC_MAX(buf, i, v) atom_max(&(buf)[i], v)
#define MV_ATOMIC_OR(buf, i, v) atom_or(&(buf)[i], v)
#define MV_ATOMIC_XCHG(buf, i, v) atom_xchg(&(buf)[i], v)
#define MV_ATOMIC_CAS(buf, i, cmp, v) atom_cmpxchg(&(buf)[i], cmp, v)
#define MV_SHARED_ATOMIC_ADD(arr, i, v) atom_add(&(arr)[i], v)
#define MV_SHARED_ATOMIC_MIN(arr, i, v) atom_min(&(arr)[i], v)
#define MV_SHARED_ATOMIC_MAX(arr, i, v) atom_max(&(arr)[i], v)
#define MV_SHARED_ATOMIC_OR(arr, i, v) atom_or(&(arr)[i], v)
#define MV_SHARED_ATOMIC_XCHG(arr, i, v) atom_xchg(&(arr)[i], v)
#define MV_SHARED_ATOMIC_CAS(arr, i, cmp, v) atom_cmpxchg(&(arr)[i], cmp, v)
#elif defined(MV_GLSL)
#define MV_ATOMIC_ADD(buf, i, val) atomicAdd((buf).v[i], val)
#define MV_ATOMIC_MIN(buf, i, val) atomicMin((buf).v[i], val)
#define MV_ATOMIC_MAX(buf, i, val) atomicMax((buf).v[i], val)
#define MV_ATOMIC_OR(buf, i, val) atomicOr((buf).v[i], val)
#define MV_ATOMIC_XCHG(buf, i, val) atomicExchange((buf).v[i], val)
#define MV_ATOMIC_CAS(buf, i, cmp, val) atomicCompSwap((buf).v[i], cmp, val)
#define MV_SHARED_ATOMIC_ADD(arr, i, v) atomicAdd((arr)[i], v)
#define MV_SHARED_ATOMIC_MIN(arr, i, v) atomicMin((arr)[i], v)
#define MV_SHARED_ATOMIC_MAX(arr, i, v) atomicMax((arr)[i], v)
#define MV_SHARED_ATOMIC_OR(arr, i, v) atomicOr((arr)[i], v)
#define MV_SHARED_ATOMIC_XCHG(arr, i, v) atomicExchange((arr)[i], v)
#define MV_SHARED_ATOMIC_CAS(arr, i, cmp, v) atomicCompSwap((arr)[i], cmp, v)
#else
#include <atomic>
template <class T>
static inline T mv_atomic_min(T* p, T v) {
  std::atomic_ref<T> a(*p);
  T old = a.load();
  while (v < old && !a.compare_exchange_weak(old, v)) {
  }
  return old;
}
template <class T>
static inline T mv_atomic_max(T* p, T v) {
  std::atomic_ref<T> a(*p);
  T old = a.load();
  while (v > old && !a.compare_exchange_weak(old, v)) {
  }
  return old;
}
template <class T>
static inline T mv_atomic_cas(T* p, T cmp, T v) {
  std::atomic_ref<T>(*p).compare_exchange_strong(cmp, v);
  return cmp;  // the value found: cmp when the swap happened
}
#define MV_ATOMIC_ADD(buf, i, v) std::atomic_ref((buf)[i]).fetch_add(v)
#define MV_ATOMIC_MIN(buf, i, v) mv_atomic_min(&(buf)[i], v)
#define MV_ATOMIC_MAX(buf, i, v) mv_atomic_max(&(buf)[i], v)
#define MV_ATOMIC_OR(buf, i, v) std::atomic_ref((buf)[i]).fetch_or(v)
#define MV_ATOMIC_XCHG(buf, i, v) std::atomic_ref((buf)[i]).exchange(v)
#define MV_ATOMIC_CAS(buf, i, cmp, v) mv_atomic_cas(&(buf)[i], cmp, v)
#define MV_SHARED_ATOMIC_ADD MV_ATOMIC_ADD
#define MV_SHARED_ATOMIC_MIN MV_ATOMIC_MIN
#define MV_SHARED_ATOMIC_MAX MV_ATOMIC_MAX
#define MV_SHARED_ATOMIC_OR MV_ATOMIC_OR
#define MV_SHARED_ATOMIC_XCHG MV_ATOMIC_XCHG
#define MV_SHARED_ATOMIC_CAS MV_ATOMIC_CAS
#endif

#endif /* MV_LANG_SYNC_H */
