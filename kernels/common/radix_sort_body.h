/* Radix sort kernel bodies for one key type. Included once per key type, with
 *   MV_KEY     the key type (mv_u32 or mv_u64)
 *   MvBufKey   its buffer type (MvBufU32 or MvBufU64)
 *   MV_KCAST(x) a cast to it (MV_U32 or MV_U64)
 *   MV_KFN(f)  the function name for this key type (f##_k32 or f##_k64)
 *   MV_RADIX_KEY_DIGITS  8-bit digits per key (4 or 8)
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

/* One stable counting-sort pass over [begin, end) of src into dst, by the digit at `shift`; `next` holds each
 * digit's first output position and is advanced. */
MV_INLINE void MV_KFN(mv_radix_local_pass)(MvBufKey src, MvBufKey dst, MvBufU32 vsrc, MvBufU32 vdst, mv_u32 has_values,
                                           mv_u32 begin, mv_u32 end, mv_u32 shift,
                                           MV_PRIVATE_ARRAY(mv_u32, next)) {
  if (has_values != 0u) {
    for (mv_u32 i = begin; i < end; ++i) {
      MV_KEY k = MV_LD(src, i);
      mv_u32 d = MV_KFN(mv_radix_digit)(k, shift);
      mv_u32 pos = next[d];
      next[d] = pos + 1u;
      MV_ST(dst, pos, k);
      MV_ST(vdst, pos, MV_LD(vsrc, i));
    }
  } else {
    for (mv_u32 i = begin; i < end; ++i) {
      MV_KEY k = MV_LD(src, i);
      mv_u32 d = MV_KFN(mv_radix_digit)(k, shift);
      mv_u32 pos = next[d];
      next[d] = pos + 1u;
      MV_ST(dst, pos, k);
    }
  }
}

/* Sorts [begin, end) of `keys` (values: `vals`) on the digits in `digits` (bit j = digit j), least significant
 * first, ping-ponging with the same range of the alt buffers; the result ends in `keys`. One read counts
 * every digit (counts do not depend on order). */
MV_INLINE void MV_KFN(mv_radix_range_lsd)(MvBufKey keys, MvBufKey keys_alt, MvBufU32 vals, MvBufU32 vals_alt,
                                          mv_u32 has_values, mv_u32 begin, mv_u32 end, mv_u32 digits) {
  mv_u32 count[MV_RADIX_KEY_DIGITS * MV_RADIX_BUCKETS];
  mv_u32 used = 0u; /* digits counted, packed: count[slot * 256 + digit value] */
  for (mv_u32 j = 0u; j < MV_U32(MV_RADIX_KEY_DIGITS); ++j)
    if ((digits & (1u << j)) != 0u) used += 1u;
  for (mv_u32 c = 0u; c < used * MV_U32(MV_RADIX_BUCKETS); ++c) count[c] = 0u;
  for (mv_u32 i = begin; i < end; ++i) {
    MV_KEY k = MV_LD(keys, i);
    mv_u32 slot = 0u;
    for (mv_u32 j = 0u; j < MV_U32(MV_RADIX_KEY_DIGITS); ++j) {
      if ((digits & (1u << j)) == 0u) continue;
      count[slot * MV_U32(MV_RADIX_BUCKETS) + MV_KFN(mv_radix_digit)(k, 8u * j)] += 1u;
      slot += 1u;
    }
  }
  bool in_alt = false; /* where the range's current order lives */
  mv_u32 next[MV_RADIX_BUCKETS];
  mv_u32 slot = 0u;
  for (mv_u32 j = 0u; j < MV_U32(MV_RADIX_KEY_DIGITS); ++j) {
    if ((digits & (1u << j)) == 0u) continue;
    mv_u32 acc = begin;
    for (mv_u32 c = 0u; c < MV_U32(MV_RADIX_BUCKETS); ++c) {
      next[c] = acc;
      acc += count[slot * MV_U32(MV_RADIX_BUCKETS) + c];
    }
    slot += 1u;
    if (in_alt) MV_KFN(mv_radix_local_pass)(keys_alt, keys, vals_alt, vals, has_values, begin, end, 8u * j, next);
    else MV_KFN(mv_radix_local_pass)(keys, keys_alt, vals, vals_alt, has_values, begin, end, 8u * j, next);
    in_alt = !in_alt;
  }
  if (in_alt) {
    for (mv_u32 i = begin; i < end; ++i) {
      MV_ST(keys, i, MV_LD(keys_alt, i));
      if (has_values != 0u) MV_ST(vals, i, MV_LD(vals_alt, i));
    }
  }
}

/* Hybrid second stage: after one global pass on the most significant varying digit has grouped the keys
 * into 256 buckets (in the alt buffers), work-item d sorts bucket d on the remaining varying digits
 * (p.local_digits, bit j = digit j) and leaves it in the main buffers: one pass on the highest of those
 * digits splits the bucket into 256 sub-buckets small enough for the first-level cache, then each
 * sub-bucket is sorted on the rest by mv_radix_range_lsd. `offsets` is the scanned histogram of the global
 * pass, so bucket d starts at offsets[d * blocks]. */
MV_INLINE void MV_KFN(mv_radix_local_sort)(MvBufKey keys, MvBufKey keys_alt, MvBufU32 vals, MvBufU32 vals_alt,
                                           MvBufU32 offsets, MvRadixParams p, mv_u32 d) {
  mv_u32 begin = MV_LD(offsets, d * p.blocks);
  mv_u32 end = d + 1u < MV_U32(MV_RADIX_BUCKETS) ? MV_LD(offsets, (d + 1u) * p.blocks) : p.n;
  mv_u32 top = 0u;
  for (mv_u32 j = 0u; j < MV_U32(MV_RADIX_KEY_DIGITS); ++j)
    if ((p.local_digits & (1u << j)) != 0u) top = j;
  mv_u32 start[MV_RADIX_BUCKETS];
  mv_u32 next[MV_RADIX_BUCKETS];
  for (mv_u32 c = 0u; c < MV_U32(MV_RADIX_BUCKETS); ++c) start[c] = 0u;
  for (mv_u32 i = begin; i < end; ++i) start[MV_KFN(mv_radix_digit)(MV_LD(keys_alt, i), 8u * top)] += 1u;
  mv_u32 acc = begin;
  for (mv_u32 c = 0u; c < MV_U32(MV_RADIX_BUCKETS); ++c) {
    mv_u32 v = start[c];
    start[c] = acc;
    next[c] = acc;
    acc += v;
  }
  MV_KFN(mv_radix_local_pass)(keys_alt, keys, vals_alt, vals, p.has_values, begin, end, 8u * top, next);
  mv_u32 rest = p.local_digits & ~(1u << top);
  if (rest == 0u) return;
  for (mv_u32 c = 0u; c < MV_U32(MV_RADIX_BUCKETS); ++c)
    if (next[c] - start[c] > 1u)
      MV_KFN(mv_radix_range_lsd)(keys, keys_alt, vals, vals_alt, p.has_values, start[c], next[c], rest);
}
