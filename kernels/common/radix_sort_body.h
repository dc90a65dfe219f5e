/* Radix sort kernel bodies for one key type. Included once per key type, with
 *   MV_KEY     the key type (mv_u32 or mv_u64)
 *   MvBufKey   its buffer type (MvBufU32 or MvBufU64)
 *   MV_KCAST(x) a cast to it (MV_U32 or MV_U64)
 *   MV_KFN(f)  the function name for this key type (f##_k32 or f##_k64)
 * No include guard on purpose. */
#include "radix_sort.h"

MV_INLINE mv_u32 MV_KFN(mv_radix_digit)(MV_KEY key, mv_u32 shift) {
  return MV_U32(key >> shift) & MV_U32(MV_RADIX_BUCKETS - 1);
}

/* OR and AND of the keys of one block: red[2b] = OR, red[2b+1] = AND (all ones for an empty block). */
MV_INLINE void MV_KFN(mv_radix_or_and)(MvBufKey keys, MvBufKey red, MvRadixParams p, mv_u32 b) {
  mv_u32 begin = b * p.block_size;
  mv_u32 end = MV_MIN(begin + p.block_size, p.n);
  MV_KEY acc_or = MV_KCAST(0);
  MV_KEY acc_and = ~MV_KCAST(0);
  for (mv_u32 i = begin; i < end; ++i) {
    MV_KEY k = MV_LD(keys, i);
    acc_or |= k;
    acc_and &= k;
  }
  MV_ST(red, 2u * b, acc_or);
  MV_ST(red, 2u * b + 1u, acc_and);
}

MV_INLINE void MV_KFN(mv_radix_histogram)(MvBufKey keys, MvBufU32 hist, MvRadixParams p, mv_u32 b) {
  mv_u32 count[MV_RADIX_BUCKETS];
  for (mv_u32 d = 0u; d < MV_U32(MV_RADIX_BUCKETS); ++d) count[d] = 0u;
  mv_u32 begin = b * p.block_size;
  mv_u32 end = MV_MIN(begin + p.block_size, p.n);
  for (mv_u32 i = begin; i < end; ++i) count[MV_KFN(mv_radix_digit)(MV_LD(keys, i), p.shift)] += 1u;
  for (mv_u32 d = 0u; d < MV_U32(MV_RADIX_BUCKETS); ++d) MV_ST(hist, d * p.blocks + b, count[d]);
}

/* Stable: keys of block b go, in order, to the positions the scanned histogram gives for (digit, b). */
MV_INLINE void MV_KFN(mv_radix_scatter)(MvBufKey keys_in, MvBufKey keys_out, MvBufU32 vals_in, MvBufU32 vals_out,
                                        MvBufU32 offsets, MvRadixParams p, mv_u32 b) {
  mv_u32 next[MV_RADIX_BUCKETS];
  for (mv_u32 d = 0u; d < MV_U32(MV_RADIX_BUCKETS); ++d) next[d] = MV_LD(offsets, d * p.blocks + b);
  mv_u32 begin = b * p.block_size;
  mv_u32 end = MV_MIN(begin + p.block_size, p.n);
  if (p.has_values != 0u) {
    for (mv_u32 i = begin; i < end; ++i) {
      MV_KEY k = MV_LD(keys_in, i);
      mv_u32 d = MV_KFN(mv_radix_digit)(k, p.shift);
      mv_u32 pos = next[d];
      next[d] = pos + 1u;
      MV_ST(keys_out, pos, k);
      MV_ST(vals_out, pos, MV_LD(vals_in, i));
    }
  } else {
    for (mv_u32 i = begin; i < end; ++i) {
      MV_KEY k = MV_LD(keys_in, i);
      mv_u32 d = MV_KFN(mv_radix_digit)(k, p.shift);
      mv_u32 pos = next[d];
      next[d] = pos + 1u;
      MV_ST(keys_out, pos, k);
    }
  }
}
