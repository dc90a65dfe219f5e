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

/* OR and AND of the keys of one block: red[2b] = OR, red[2b+1] = AND (all ones for an empty block). With
 * p.count != 0 it also writes the block's histogram of the digit at p.shift, as radix_histogram does: a guess
 * at the first digit the host will sort on, which saves that pass's read of every key when it is right. */
MV_INLINE void MV_KFN(mv_radix_or_and)(MvBufKey keys, MvBufKey red, MvBufU32 hist, MvRadixParams p, mv_u32 b) {
  mv_u32 begin = b * p.block_size;
  mv_u32 end = MV_MIN(begin + p.block_size, p.n);
  MV_KEY acc_or = MV_KCAST(0);
  MV_KEY acc_and = ~MV_KCAST(0);
  if (p.count != 0u) {
    mv_u32 count[MV_RADIX_BUCKETS];
    for (mv_u32 d = 0u; d < MV_U32(MV_RADIX_BUCKETS); ++d) count[d] = 0u;
    for (mv_u32 i = begin; i < end; ++i) {
      MV_KEY k = MV_LD(keys, i);
      acc_or |= k;
      acc_and &= k;
      count[MV_KFN(mv_radix_digit)(k, p.shift)] += 1u;
    }
    for (mv_u32 d = 0u; d < MV_U32(MV_RADIX_BUCKETS); ++d) MV_ST(hist, d * p.blocks + b, count[d]);
  } else {
    for (mv_u32 i = begin; i < end; ++i) {
      MV_KEY k = MV_LD(keys, i);
      acc_or |= k;
      acc_and &= k;
    }
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

/* One stable counting-sort pass over [begin, end) by the digit at `shift`: key i is read at src[i + soff] and
 * written at dst[pos + doff], where `next` holds each digit's first output position and is advanced. The
 * offsets let the hybrid's in-bucket passes use a scratch slice at another place than the bucket (indices wrap
 * modulo 2^32, so an offset may be "negative"). */
MV_INLINE void MV_KFN(mv_radix_pass)(MvBufKey src, mv_u32 soff, MvBufKey dst, mv_u32 doff, MvBufU32 vsrc,
                                     MvBufU32 vdst, mv_u32 has_values, mv_u32 begin, mv_u32 end, mv_u32 shift,
                                     MV_ARRAY256_PARAM(mv_u32, next)) {
  if (has_values != 0u) {
    for (mv_u32 i = begin; i < end; ++i) {
      MV_KEY k = MV_LD(src, i + soff);
      mv_u32 d = MV_KFN(mv_radix_digit)(k, shift);
      mv_u32 pos = next[d];
      next[d] = pos + 1u;
      MV_ST(dst, pos + doff, k);
      MV_ST(vdst, pos + doff, MV_LD(vsrc, i + soff));
    }
  } else {
    for (mv_u32 i = begin; i < end; ++i) {
      MV_KEY k = MV_LD(src, i + soff);
      mv_u32 d = MV_KFN(mv_radix_digit)(k, shift);
      mv_u32 pos = next[d];
      next[d] = pos + 1u;
      MV_ST(dst, pos + doff, k);
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
  MV_KFN(mv_radix_pass)(keys_in, 0u, keys_out, 0u, vals_in, vals_out, p.has_values, begin, end, p.shift, next);
}

/* The same pass through per-digit line buffers: each digit's keys (and values) gather in a private buffer of
 * MV_RADIX_LINE entries that mirrors one aligned run of output positions, and a run the block fills whole goes
 * out at once with streaming stores (MV_ST_STREAM), which skip the read for ownership and leave the caches to
 * the input. Runs shared with a neighbouring block's range, and the last partial run of each digit, go out with
 * plain stores, entry by entry. On a CPU device this makes the global pass about 3x faster than
 * mv_radix_scatter, which sends every key to one of 256 lines that each cost a read from memory; on a device
 * without streaming stores it is the same writes in another order. */
MV_INLINE void MV_KFN(mv_radix_scatter_stream)(MvBufKey keys_in, MvBufKey keys_out, MvBufU32 vals_in,
                                               MvBufU32 vals_out, MvBufU32 offsets, MvRadixParams p, mv_u32 b) {
  MV_KEY kbuf[MV_RADIX_BUCKETS * MV_RADIX_LINE];
  mv_u32 vbuf[MV_RADIX_BUCKETS * MV_RADIX_LINE];
  mv_u32 first[MV_RADIX_BUCKETS];
  mv_u32 next[MV_RADIX_BUCKETS];
  for (mv_u32 d = 0u; d < MV_U32(MV_RADIX_BUCKETS); ++d) {
    first[d] = MV_LD(offsets, d * p.blocks + b);
    next[d] = first[d];
  }
  const mv_u32 line = MV_U32(MV_RADIX_LINE);
  mv_u32 begin = b * p.block_size;
  mv_u32 end = MV_MIN(begin + p.block_size, p.n);
  for (mv_u32 i = begin; i < end; ++i) {
    MV_KEY k = MV_LD(keys_in, i);
    mv_u32 d = MV_KFN(mv_radix_digit)(k, p.shift);
    mv_u32 pos = next[d];
    mv_u32 slot = d * line + (pos & (line - 1u));
    kbuf[slot] = k;
    if (p.has_values != 0u) vbuf[slot] = MV_LD(vals_in, i);
    pos += 1u;
    next[d] = pos;
    if ((pos & (line - 1u)) == 0u) { /* the buffer's run is complete: send what of it is this block's */
      mv_u32 run = pos - line;
      mv_u32 from = MV_MAX(run, first[d]);
      if (from == run) {
        for (mv_u32 j = 0u; j < line; ++j) MV_ST_STREAM(keys_out, run + j, kbuf[d * line + j]);
        if (p.has_values != 0u)
          for (mv_u32 j = 0u; j < line; ++j) MV_ST_STREAM(vals_out, run + j, vbuf[d * line + j]);
      } else {
        for (mv_u32 q = from; q < pos; ++q) MV_ST(keys_out, q, kbuf[d * line + (q & (line - 1u))]);
        if (p.has_values != 0u)
          for (mv_u32 q = from; q < pos; ++q) MV_ST(vals_out, q, vbuf[d * line + (q & (line - 1u))]);
      }
    }
  }
  for (mv_u32 d = 0u; d < MV_U32(MV_RADIX_BUCKETS); ++d) { /* the partial runs left */
    mv_u32 pos = next[d];
    mv_u32 from = MV_MAX(pos & ~(line - 1u), first[d]);
    for (mv_u32 q = from; q < pos; ++q) MV_ST(keys_out, q, kbuf[d * line + (q & (line - 1u))]);
    if (p.has_values != 0u)
      for (mv_u32 q = from; q < pos; ++q) MV_ST(vals_out, q, vbuf[d * line + (q & (line - 1u))]);
  }
  MV_STREAM_FENCE();
}

/* Stable insertion sort of [begin, end): key i read at src[i + soff] (values vsrc), the result in the same range
 * of keys (values vals); src may be keys itself (soff 0). Finishes the ranges the in-bucket MSD passes leave
 * small. */
MV_INLINE void MV_KFN(mv_radix_insertion)(MvBufKey src, MvBufU32 vsrc, mv_u32 soff, MvBufKey keys, MvBufU32 vals,
                                          mv_u32 has_values, mv_u32 begin, mv_u32 end) {
  for (mv_u32 i = begin; i < end; ++i) {
    MV_KEY k = MV_LD(src, i + soff);
    mv_u32 v = has_values != 0u ? MV_LD(vsrc, i + soff) : 0u;
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

/* Hybrid second stage. One global pass on the most significant varying digit (at p.local_top) has grouped the
 * keys into 256 buckets in `keys` (values `vals`); each bucket of [p.bucket_first, p.bucket_end) is sorted there
 * on bits [p.local_low, p.local_top), the bits below the top digit that vary. Work-items take buckets from a
 * counter until none of the range is left (offsets[blocks * 256 + 1], p.bucket_first before the dispatch), each
 * moving its bucket through a scratch slice of `scratch` (values `vscratch`) that starts at w * p.scratch_stride
 * and is reused for every bucket it takes, so it stays in cache. With p.scratch_stride 0 (where loops are
 * capped) work-item w sorts bucket p.bucket_first + w alone, through the bucket's own range of `scratch`.
 * Within a bucket it is an MSD radix sort on 8-bit digits: a range whose keys agree on every bit from `top` up
 * is split on the digit just below `top` (ping-ponging between bucket and slice), a range of at most
 * MV_RADIX_SMALL keys (or whose children are all that small) is finished by insertion sort back into the
 * bucket, and a digit on which a whole range agrees is skipped without moving anything. Random keys are done
 * after two in-bucket passes. Recursion is an explicit stack of at most one frame per digit. `offsets` is the
 * global pass's scanned histogram, so bucket d starts at offsets[d * blocks]. */
MV_INLINE void MV_KFN(mv_radix_local_sort)(MvBufKey keys, MvBufKey scratch, MvBufU32 vals, MvBufU32 vscratch,
                                           MvBufU32 offsets, MvRadixParams p, mv_u32 w) {
  mv_u32 bounds[MV_RADIX_KEY_DIGITS * (MV_RADIX_BUCKETS + 1)]; /* per frame: its children's ranges */
  mv_u32 frame_child[MV_RADIX_KEY_DIGITS];                     /* per frame: next child to visit */
  mv_u32 frame_top[MV_RADIX_KEY_DIGITS];                       /* per frame: the children's top bit */
  mv_u32 frame_slice[MV_RADIX_KEY_DIGITS];                     /* per frame: children live in the slice (1) */
  mv_u32 count[MV_RADIX_BUCKETS]; /* zero between ranges */
  mv_u32 next[MV_RADIX_BUCKETS];
  for (mv_u32 c = 0u; c < MV_U32(MV_RADIX_BUCKETS); ++c) count[c] = 0u;
  const mv_u32 counter = p.blocks * MV_U32(MV_RADIX_BUCKETS) + 1u;
  mv_u32 d = p.scratch_stride != 0u ? MV_ATOMIC_ADD(offsets, counter, 1u) : p.bucket_first + w;
  for (; d < p.bucket_end; d = p.scratch_stride != 0u ? MV_ATOMIC_ADD(offsets, counter, 1u) : d + 256u) {
    mv_u32 b = MV_LD(offsets, d * p.blocks);
    mv_u32 e = d + 1u < MV_U32(MV_RADIX_BUCKETS) ? MV_LD(offsets, (d + 1u) * p.blocks) : p.n;
    mv_u32 soff = p.scratch_stride != 0u ? w * p.scratch_stride - b : 0u; /* slice index = bucket index + soff */
    mv_u32 depth = 0u;
    mv_u32 in_slice = 0u; /* where the range being processed lives */
    mv_u32 top = p.local_top;
    bool have = e - b > 1u;
    while (have) {
      /* Descend: split the range on the digit below `top`, or finish it. */
      while (true) {
        if (e - b <= MV_U32(MV_RADIX_SMALL) || top <= p.local_low) {
          if (in_slice != 0u) MV_KFN(mv_radix_insertion)(scratch, vscratch, soff, keys, vals, p.has_values, b, e);
          else if (e - b > 1u) MV_KFN(mv_radix_insertion)(keys, vals, 0u, keys, vals, p.has_values, b, e);
          break;
        }
        mv_u32 shift = top >= p.local_low + 8u ? top - 8u : p.local_low;
        if (in_slice != 0u)
          for (mv_u32 i = b; i < e; ++i) count[MV_KFN(mv_radix_digit)(MV_LD(scratch, i + soff), shift)] += 1u;
        else
          for (mv_u32 i = b; i < e; ++i) count[MV_KFN(mv_radix_digit)(MV_LD(keys, i), shift)] += 1u;
        /* One loop lays out the children, finds the largest and clears the counts for the next range. */
        mv_u32 base = depth * MV_U32(MV_RADIX_BUCKETS + 1);
        mv_u32 acc = b;
        mv_u32 largest = 0u;
        for (mv_u32 c = 0u; c < MV_U32(MV_RADIX_BUCKETS); ++c) {
          mv_u32 size = count[c];
          count[c] = 0u;
          largest = MV_MAX(largest, size);
          bounds[base + c] = acc;
          next[c] = acc;
          acc += size;
        }
        if (largest == e - b) { /* the whole range agrees on this digit */
          top = shift;
          continue;
        }
        bounds[base + MV_U32(MV_RADIX_BUCKETS)] = e;
        if (in_slice != 0u)
          MV_KFN(mv_radix_pass)(scratch, soff, keys, 0u, vscratch, vals, p.has_values, b, e, shift, next);
        else
          MV_KFN(mv_radix_pass)(keys, 0u, scratch, soff, vals, vscratch, p.has_values, b, e, shift, next);
        if (largest <= MV_U32(MV_RADIX_SMALL)) {
          /* Every child is small: one insertion pass over the whole range finishes them all, since each key
           * only moves within its own child (later children hold larger keys). */
          if (in_slice != 0u) MV_KFN(mv_radix_insertion)(keys, vals, 0u, keys, vals, p.has_values, b, e);
          else MV_KFN(mv_radix_insertion)(scratch, vscratch, soff, keys, vals, p.has_values, b, e);
          break;
        }
        frame_child[depth] = 0u;
        frame_top[depth] = shift;
        frame_slice[depth] = 1u - in_slice;
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
        in_slice = frame_slice[f];
        top = frame_top[f];
        have = e > b;
      }
    }
  }
}
