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

/* One stable counting-sort pass over [begin, end) of src into dst, by the digit at `shift`; `next` holds each
 * digit's first output position and is advanced. */
MV_INLINE void MV_KFN(mv_radix_pass)(MvBufKey src, MvBufKey dst, MvBufU32 vsrc, MvBufU32 vdst, mv_u32 has_values,
                                           mv_u32 begin, mv_u32 end, mv_u32 shift,
                                           MV_ARRAY256_PARAM(mv_u32, next)) {
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

/* Stable: keys of block b go, in order, to the positions the scanned histogram gives for (digit, b). */
MV_INLINE void MV_KFN(mv_radix_scatter)(MvBufKey keys_in, MvBufKey keys_out, MvBufU32 vals_in, MvBufU32 vals_out,
                                        MvBufU32 offsets, MvRadixParams p, mv_u32 b) {
  mv_u32 next[MV_RADIX_BUCKETS];
  for (mv_u32 d = 0u; d < MV_U32(MV_RADIX_BUCKETS); ++d) next[d] = MV_LD(offsets, d * p.blocks + b);
  mv_u32 begin = b * p.block_size;
  mv_u32 end = MV_MIN(begin + p.block_size, p.n);
  MV_KFN(mv_radix_pass)(keys_in, keys_out, vals_in, vals_out, p.has_values, begin, end, p.shift, next);
}

/* Stable insertion sort of [begin, end) of src (values vsrc) into the same range of keys (values vals);
 * src may be keys itself. Finishes the ranges the in-bucket MSD passes leave small. */
MV_INLINE void MV_KFN(mv_radix_insertion)(MvBufKey src, MvBufU32 vsrc, MvBufKey keys, MvBufU32 vals, mv_u32 has_values,
                                          mv_u32 begin, mv_u32 end) {
  for (mv_u32 i = begin; i < end; ++i) {
    MV_KEY k = MV_LD(src, i);
    mv_u32 v = has_values != 0u ? MV_LD(vsrc, i) : 0u;
    mv_u32 j = i;
    while (j > begin && MV_LD(keys, j - 1u) > k) { /* strictly greater keeps equal keys in order */
      MV_ST(keys, j, MV_LD(keys, j - 1u));
      if (has_values != 0u) MV_ST(vals, j, MV_LD(vals, j - 1u));
      j -= 1u;
    }
    MV_ST(keys, j, k);
    if (has_values != 0u) MV_ST(vals, j, v);
  }
}

/* Hybrid second stage: after one global pass on the most significant varying digit has grouped the keys
 * into 256 buckets (in the alt buffers), work-item d sorts bucket d on the remaining varying digits
 * (p.local_digits, bit j = digit j) and leaves it in the main buffers. Within the bucket it is an MSD
 * radix sort: each range is split on its next digit (moving between the main and alt buffers), ranges of
 * at most MV_RADIX_SMALL keys (or splits into such children only) are finished by insertion sort, and a
 * digit on which a whole range agrees is
 * skipped without moving anything. Random keys are done after about two in-bucket passes instead of one per
 * digit. Recursion is an explicit stack of at most one frame per digit. `offsets` is the scanned histogram
 * of the global pass, so bucket d starts at offsets[d * blocks]. */
MV_INLINE void MV_KFN(mv_radix_local_sort)(MvBufKey keys, MvBufKey keys_alt, MvBufU32 vals, MvBufU32 vals_alt,
                                           MvBufU32 offsets, MvRadixParams p, mv_u32 d) {
  mv_u32 digit[MV_RADIX_KEY_DIGITS]; /* local digits, most significant first */
  mv_u32 ndigits = 0u;
  for (mv_u32 j = MV_U32(MV_RADIX_KEY_DIGITS); j > 0u; --j)
    if ((p.local_digits & (1u << (j - 1u))) != 0u) {
      digit[ndigits] = j - 1u;
      ndigits += 1u;
    }
  mv_u32 bounds[MV_RADIX_KEY_DIGITS * (MV_RADIX_BUCKETS + 1)]; /* per frame: its children's ranges */
  mv_u32 frame_child[MV_RADIX_KEY_DIGITS];                     /* per frame: next child to visit */
  mv_u32 frame_level[MV_RADIX_KEY_DIGITS];                     /* per frame: the children's digit level */
  mv_u32 frame_alt[MV_RADIX_KEY_DIGITS];                       /* per frame: children live in alt (1) or main */
  mv_u32 count[MV_RADIX_BUCKETS];
  mv_u32 next[MV_RADIX_BUCKETS];
  mv_u32 depth = 0u;
  /* the range being processed */
  mv_u32 b = MV_LD(offsets, d * p.blocks);
  mv_u32 e = d + 1u < MV_U32(MV_RADIX_BUCKETS) ? MV_LD(offsets, (d + 1u) * p.blocks) : p.n;
  mv_u32 alt = 1u;
  mv_u32 level = 0u;
  bool have = e > b;
  while (have) {
    /* Descend: split the range on its next digit, or finish it. */
    while (true) {
      if (e - b <= MV_U32(MV_RADIX_SMALL) || level == ndigits) {
        if (alt != 0u) MV_KFN(mv_radix_insertion)(keys_alt, vals_alt, keys, vals, p.has_values, b, e);
        else if (e - b > 1u) MV_KFN(mv_radix_insertion)(keys, vals, keys, vals, p.has_values, b, e);
        break;
      }
      mv_u32 shift = 8u * digit[level];
      for (mv_u32 c = 0u; c < MV_U32(MV_RADIX_BUCKETS); ++c) count[c] = 0u;
      for (mv_u32 i = b; i < e; ++i)
        count[MV_KFN(mv_radix_digit)(alt != 0u ? MV_LD(keys_alt, i) : MV_LD(keys, i), shift)] += 1u;
      mv_u32 largest = 0u;
      for (mv_u32 c = 0u; c < MV_U32(MV_RADIX_BUCKETS); ++c) largest = MV_MAX(largest, count[c]);
      if (largest == e - b) { /* the whole range agrees on this digit */
        level += 1u;
        continue;
      }
      mv_u32 base = depth * MV_U32(MV_RADIX_BUCKETS + 1);
      mv_u32 acc = b;
      for (mv_u32 c = 0u; c < MV_U32(MV_RADIX_BUCKETS); ++c) {
        bounds[base + c] = acc;
        next[c] = acc;
        acc += count[c];
      }
      bounds[base + MV_U32(MV_RADIX_BUCKETS)] = e;
      if (alt != 0u) MV_KFN(mv_radix_pass)(keys_alt, keys, vals_alt, vals, p.has_values, b, e, shift, next);
      else MV_KFN(mv_radix_pass)(keys, keys_alt, vals, vals_alt, p.has_values, b, e, shift, next);
      if (largest <= MV_U32(MV_RADIX_SMALL)) {
        /* Every child is small: one insertion pass over the whole range finishes them all, since each key
         * only moves within its own child (later children hold larger keys). */
        if (alt != 0u) MV_KFN(mv_radix_insertion)(keys, vals, keys, vals, p.has_values, b, e);
        else MV_KFN(mv_radix_insertion)(keys_alt, vals_alt, keys, vals, p.has_values, b, e);
        break;
      }
      frame_child[depth] = 0u;
      frame_level[depth] = level + 1u;
      frame_alt[depth] = 1u - alt;
      depth += 1u;
      break;
    }
    /* Ascend: the next non-empty child of the deepest frame that has one. */
    have = false;
    while (depth > 0u && !have) {
      mv_u32 f = depth - 1u;
      mv_u32 c = frame_child[f];
      if (c == MV_U32(MV_RADIX_BUCKETS)) {
        depth -= 1u;
        continue;
      }
      frame_child[f] = c + 1u;
      b = bounds[f * MV_U32(MV_RADIX_BUCKETS + 1) + c];
      e = bounds[f * MV_U32(MV_RADIX_BUCKETS + 1) + c + 1u];
      alt = frame_alt[f];
      level = frame_level[f];
      have = e > b;
    }
  }
}
