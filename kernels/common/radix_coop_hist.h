/* Cooperative radix histogram for one key type (macros as radix_sort_body.h; no include guard on purpose).
 * A .comp declares MV_SHARED(mv_u32, aux, MV_COOP_AUX) before including it.
 *
 * Work-group g counts the digit at p.shift over each block of MV_COOP_BLOCK keys it takes (blocks g, g + groups,
 * ...) with shared atomics, and writes hist[digit * blocks + block], digit-major as the block-per-work-item
 * histogram, so the same scan turns it into output positions. */
MV_INLINE void MV_KFN(mv_radix_coop_histogram)(MV_SHARED_PARAM(mv_u32, aux) MvBufKey keys, MvBufU32 hist,
                                               MvRadixParams p) {
  mv_u32 t = MV_LOCAL_ID();
  for (mv_u32 blk = MV_GROUP_ID(); blk < p.blocks; blk += MV_NUM_GROUPS()) {
    for (mv_u32 d = t; d < MV_U32(MV_RADIX_BUCKETS); d += MV_U32(MV_COOP_WG)) aux[d] = 0u;
    MV_BARRIER();
    mv_u32 begin = blk * p.block_size;
    mv_u32 end = MV_MIN(begin + p.block_size, p.n);
    for (mv_u32 i = begin + t; i < end; i += MV_U32(MV_COOP_WG))
      MV_SHARED_ATOMIC_ADD(aux, MV_KFN(mv_radix_digit)(MV_LD(keys, i), p.shift), 1u);
    MV_BARRIER();
    for (mv_u32 d = t; d < MV_U32(MV_RADIX_BUCKETS); d += MV_U32(MV_COOP_WG)) MV_ST(hist, d * p.blocks + blk, aux[d]);
    MV_BARRIER();
  }
}
