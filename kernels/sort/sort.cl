// OpenCL entry points of the radix sort (bodies: common/radix_sort_body.h and the cooperative variant's
// common/radix_coop_*.h, one instance per key type).
#include "common/radix_sort.h"

#define MV_KEY uint
#define MvBufKey __global uint*
#define MV_KCAST(x) MV_U32(x)
#define MV_KFN(f) f##_k32
#define MV_RADIX_KEY_DIGITS 4
#include "common/radix_sort_body.h"
#include "common/radix_coop_hist.h"
#include "common/radix_coop_scatter.h"
#undef MV_RADIX_KEY_DIGITS
#undef MV_KEY
#undef MvBufKey
#undef MV_KCAST
#undef MV_KFN

#define MV_KEY ulong
#define MvBufKey __global ulong*
#define MV_KCAST(x) MV_U64(x)
#define MV_KFN(f) f##_k64
#define MV_RADIX_KEY_DIGITS 8
#include "common/radix_sort_body.h"
#include "common/radix_coop_hist.h"
#include "common/radix_coop_scatter.h"

#define MV_RADIX_ENTRIES(K, KT)                                                                               \
  __kernel void radix_or_and_##K(__global KT* keys, __global KT* red, __global uint* hist, MvRadixParams p) { \
    uint b = MV_GLOBAL_ID();                                                                                  \
    if (b < p.blocks) mv_radix_or_and_##K(keys, red, hist, p, b);                                            \
  }                                                                                                           \
  __kernel void radix_histogram_##K(__global KT* keys, __global uint* hist, MvRadixParams p) {                \
    uint b = MV_GLOBAL_ID();                                                                                  \
    if (b < p.blocks) mv_radix_histogram_##K(keys, hist, p, b);                                              \
  }                                                                                                           \
  __kernel void radix_scatter_##K(__global KT* keys_in, __global KT* keys_out, __global uint* vals_in,         \
                                  __global uint* vals_out, __global uint* offsets, MvRadixParams p) {         \
    uint b = MV_GLOBAL_ID();                                                                                  \
    if (b < p.blocks) mv_radix_scatter_##K(keys_in, keys_out, vals_in, vals_out, offsets, p, b);             \
  }                                                                                                           \
  __kernel void radix_scatter_stream_##K(__global KT* keys_in, __global KT* keys_out, __global uint* vals_in,  \
                                         __global uint* vals_out, __global uint* offsets, MvRadixParams p) {  \
    uint b = MV_GLOBAL_ID();                                                                                  \
    if (b < p.blocks) mv_radix_scatter_stream_##K(keys_in, keys_out, vals_in, vals_out, offsets, p, b);      \
  }                                                                                                           \
  __kernel void radix_local_sort_##K(__global KT* keys, __global KT* scratch, __global uint* vals,           \
                                     __global uint* vscratch, __global uint* offsets, MvRadixParams p) {      \
    mv_radix_local_sort_##K(keys, scratch, vals, vscratch, offsets, p, MV_GLOBAL_ID());                      \
  }                                                                                                           \
  __kernel void radix_coop_histogram_##K(__global KT* keys, __global uint* hist, MvRadixParams p) {           \
    MV_SHARED(uint, aux, MV_COOP_AUX);                                                                        \
    mv_radix_coop_histogram_##K(aux, keys, hist, p);                                                          \
  }                                                                                                           \
  __kernel void radix_coop_scatter_##K(__global KT* keys_in, __global KT* keys_out, __global uint* vals_in,    \
                                       __global uint* vals_out, __global uint* offsets, MvRadixParams p) {    \
    MV_SHARED(KT, ks, MV_COOP_TILE);                                                                          \
    MV_SHARED(uint, vs, MV_COOP_TILE);                                                                        \
    MV_SHARED(uint, cnt, MV_COOP_COUNTERS);                                                                   \
    MV_SHARED(uint, aux, MV_COOP_AUX);                                                                        \
    mv_radix_coop_scatter_##K(ks, vs, cnt, aux, keys_in, keys_out, vals_in, vals_out, offsets, p);            \
  }

MV_RADIX_ENTRIES(k32, uint)
MV_RADIX_ENTRIES(k64, ulong)
