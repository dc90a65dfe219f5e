/* Cooperative stable radix scatter for one key type (macros as radix_sort_body.h; no include guard on purpose).
 * A .comp declares, before including it:
 *   MV_SHARED(MV_KEY, ks, MV_COOP_TILE)  MV_SHARED(mv_u32, vs, MV_COOP_TILE)
 *   MV_SHARED(mv_u32, cnt, MV_COOP_COUNTERS)  MV_SHARED(mv_u32, aux, MV_COOP_AUX)
 *
 * Work-group g takes blocks g, g + groups, ... and walks each in tiles of MV_COOP_TILE keys. A tile is first
 * sorted stably by its digit in shared memory: two counting passes on 4-bit sub-digits, low then high. Item t
 * holds keys t * ITEMS .. t * ITEMS + ITEMS - 1 of the current order in registers, counts them in its own column
 * of cnt (cnt[nibble * WG + t], so no atomics), one work-group scan of cnt in (nibble, item) order gives each
 * (nibble, item) its first position, and the item writes its keys there in order: equal sub-digits keep their
 * order, so the pass is stable without any assumption about subgroups. Then every key of digit d goes to
 * base[d] + (its position - the digit's first position in the tile), base[d] starting at the scanned histogram's
 * offset for (d, block) and advancing by the digit's count per tile: consecutive items write consecutive
 * addresses. A tile past the end is padded with all-ones keys, which sort after every real key and are not
 * written. Barriers are all in uniform control flow; no work-group waits for another. */
#define MV_COOP_FIRST 0u
#define MV_COOP_END MV_U32(MV_RADIX_BUCKETS)
#define MV_COOP_BASE MV_U32(2 * MV_RADIX_BUCKETS)
#define MV_COOP_PART MV_U32(3 * MV_RADIX_BUCKETS)

/* Exclusive scan of cnt (MV_COOP_COUNTERS words) by the work-group: each item sums its run of
 * MV_COOP_NIBBLES words, item 0 scans the MV_COOP_WG run sums (two barriers, where a tree scan would take one
 * per level: barriers are what costs on lavapipe), and each item adds its prefix. */
MV_INLINE void MV_KFN(mv_radix_coop_scan)(MV_SHARED_PARAM(mv_u32, cnt) MV_SHARED_PARAM(mv_u32, aux) mv_u32 t) {
  mv_u32 run = t * MV_U32(MV_COOP_NIBBLES);
  mv_u32 sum = 0u;
  for (mv_u32 j = 0u; j < MV_U32(MV_COOP_NIBBLES); ++j) sum += cnt[run + j];
  aux[MV_COOP_PART + t] = sum;
  MV_BARRIER();
  if (t == 0u) {
    mv_u32 acc = 0u;
    for (mv_u32 i = 0u; i < MV_U32(MV_COOP_WG); ++i) {
      mv_u32 x = aux[MV_COOP_PART + i];
      aux[MV_COOP_PART + i] = acc;
      acc += x;
    }
  }
  MV_BARRIER();
  mv_u32 acc = aux[MV_COOP_PART + t];
  for (mv_u32 j = 0u; j < MV_U32(MV_COOP_NIBBLES); ++j) {
    mv_u32 c = cnt[run + j];
    cnt[run + j] = acc;
    acc += c;
  }
  MV_BARRIER();
}

MV_INLINE mv_u32 MV_KFN(mv_radix_coop_nibble)(MV_KEY key, mv_u32 shift, mv_u32 sub) {
  return (MV_KFN(mv_radix_digit)(key, shift) >> (4u * sub)) & 15u;
}

MV_INLINE void MV_KFN(mv_radix_coop_scatter)(MV_SHARED_PARAM(MV_KEY, ks) MV_SHARED_PARAM(mv_u32, vs)
                                                 MV_SHARED_PARAM(mv_u32, cnt) MV_SHARED_PARAM(mv_u32, aux)
                                                     MvBufKey keys_in,
                                             MvBufKey keys_out, MvBufU32 vals_in, MvBufU32 vals_out,
                                             MvBufU32 offsets, MvRadixParams p) {
  mv_u32 t = MV_LOCAL_ID();
  MV_KEY k[MV_COOP_ITEMS];
  mv_u32 v[MV_COOP_ITEMS];
  for (mv_u32 blk = MV_GROUP_ID(); blk < p.blocks; blk += MV_NUM_GROUPS()) {
    for (mv_u32 d = t; d < MV_U32(MV_RADIX_BUCKETS); d += MV_U32(MV_COOP_WG))
      aux[MV_COOP_BASE + d] = MV_LD(offsets, d * p.blocks + blk);
    mv_u32 begin = blk * p.block_size;
    mv_u32 end = MV_MIN(begin + p.block_size, p.n);
    for (mv_u32 tile = begin; tile < end; tile += MV_U32(MV_COOP_TILE)) {
      mv_u32 valid = MV_MIN(end - tile, MV_U32(MV_COOP_TILE));
      for (mv_u32 j = 0u; j < MV_U32(MV_COOP_ITEMS); ++j) {
        mv_u32 i = t * MV_U32(MV_COOP_ITEMS) + j;
        k[j] = i < valid ? MV_LD(keys_in, tile + i) : ~MV_KCAST(0);
        v[j] = i < valid && p.has_values != 0u ? MV_LD(vals_in, tile + i) : 0u;
      }
      for (mv_u32 sub = 0u; sub < 2u; ++sub) {
        for (mv_u32 c = 0u; c < MV_U32(MV_COOP_NIBBLES); ++c) cnt[c * MV_U32(MV_COOP_WG) + t] = 0u;
        for (mv_u32 j = 0u; j < MV_U32(MV_COOP_ITEMS); ++j)
          cnt[MV_KFN(mv_radix_coop_nibble)(k[j], p.shift, sub) * MV_U32(MV_COOP_WG) + t] += 1u;
        MV_BARRIER();
        MV_KFN(mv_radix_coop_scan)(MV_SHARED_ARG(cnt) MV_SHARED_ARG(aux) t);
        for (mv_u32 j = 0u; j < MV_U32(MV_COOP_ITEMS); ++j) {
          mv_u32 c = MV_KFN(mv_radix_coop_nibble)(k[j], p.shift, sub) * MV_U32(MV_COOP_WG) + t;
          mv_u32 pos = cnt[c];
          cnt[c] = pos + 1u;
          ks[pos] = k[j];
          vs[pos] = v[j];
        }
        MV_BARRIER();
        for (mv_u32 j = 0u; j < MV_U32(MV_COOP_ITEMS); ++j) {
          k[j] = ks[t * MV_U32(MV_COOP_ITEMS) + j];
          v[j] = vs[t * MV_U32(MV_COOP_ITEMS) + j];
        }
        for (mv_u32 d = t; d < MV_U32(MV_RADIX_BUCKETS); d += MV_U32(MV_COOP_WG)) {
          aux[MV_COOP_FIRST + d] = 0u;
          aux[MV_COOP_END + d] = 0u;
        }
        MV_BARRIER();
      }
      /* The tile is sorted by digit in ks / vs: find where each digit's run starts and ends. */
      for (mv_u32 i = t; i < valid; i += MV_U32(MV_COOP_WG)) {
        mv_u32 d = MV_KFN(mv_radix_digit)(ks[i], p.shift);
        if (i == 0u || MV_KFN(mv_radix_digit)(ks[i - 1u], p.shift) != d) aux[MV_COOP_FIRST + d] = i;
        if (i + 1u == valid || MV_KFN(mv_radix_digit)(ks[i + 1u], p.shift) != d) aux[MV_COOP_END + d] = i + 1u;
      }
      MV_BARRIER();
      for (mv_u32 i = t; i < valid; i += MV_U32(MV_COOP_WG)) {
        MV_KEY key = ks[i];
        mv_u32 d = MV_KFN(mv_radix_digit)(key, p.shift);
        mv_u32 pos = aux[MV_COOP_BASE + d] + i - aux[MV_COOP_FIRST + d];
        MV_ST(keys_out, pos, key);
        if (p.has_values != 0u) MV_ST(vals_out, pos, vs[i]);
      }
      MV_BARRIER();
      for (mv_u32 d = t; d < MV_U32(MV_RADIX_BUCKETS); d += MV_U32(MV_COOP_WG))
        aux[MV_COOP_BASE + d] += aux[MV_COOP_END + d] - aux[MV_COOP_FIRST + d];
      MV_BARRIER();
    }
  }
}

#undef MV_COOP_FIRST
#undef MV_COOP_END
#undef MV_COOP_BASE
#undef MV_COOP_PART
