/* Ray traversal of the encoded voxel DAGs, written once for the host, OpenCL C and GLSL: the loop. Records
 * and parameters are in trace_types.h, ray setup and crossing arithmetic in trace_ray.h, what it reads of
 * each node in trace_nodes.h, the paged address layer in trace_paging.h.
 *
 * The traversal is the "transform the geometry" multi-level DDA of Jaspe Villanueva's SSVDAG (PhD thesis,
 * 2018, ch. 5): the ray stays fixed, a 3-bit mirror mask M is accumulated along the path, and the child seen in
 * octant v is stored at slot v ^ M.
 *
 * Coordinates: the root cube is [0, 1)^3 (host maps world to this cube); a cell of level l has side
 * 2^(l - L). Every decision is a comparison of crossing times t = (b - o) * inv_d, where b is a cell
 * boundary (exact in float), inv_d a deterministic reciprocal (mv_rcp: integer seed + Newton steps, only
 * correctly rounded + - *). Crossings are ordered by (t, axis): at equal t the lower axis is crossed first.
 * So the walk is the same on every device, and equals a flat DDA over the voxels (host/ref) bit for bit:
 * a coarse boundary is also a fine one with the same float t, and a descent picks the child half by asking
 * whether the ray crossed the cell's mid plane before the event that brought it into the cell.
 *
 * A ray stops at the first full cell that is a voxel, or (LOD) whose side s satisfies s * proj < t + lod_t
 * (proj = 0: voxels only). A ray starting inside the cube starts in the cell it is in just before t = 0
 * (on a boundary: the cell behind it), so it reports a hit at t = 0 without a face only when it starts in a
 * full voxel.
 *
 * The loop body is written for SIMD devices that run every branch under a mask: lavapipe executes each
 * load and each indexed access to the per-level arrays as a loop over its lanes whether any lane takes
 * the branch or not, so the ssvdag descent has one straight path with two loads (the pointer's two
 * 16-bit halves as one 64-bit read, then the child's header or brick as another), and level offsets
 * may come from the parameters (mv_level_base). Every read of the node streams is an mv_node_load
 * (trace_nodes.h), the seam where a paged address layer goes. */
#ifndef MV_TRACE_H
#define MV_TRACE_H
#include "trace_nodes.h"
#include "trace_paging.h"
#include "trace_ray.h"

/* One ray through the DAG of MV_TRACE_LEVELS(p) levels (p.proj, p.max_steps; `variant`: mv_trace_rays), from
 * t = `start` where that is > 0 (no event at t <= start may be a hit: mv_restart; the same hit, fewer steps). enc =
 * MV_ENC_PAGED: `words` are the cache's slots, `bricks` its page table, usage / request its stamps
 * (mv_page_resolve), and the walk stops at the finest resident cell on its way: a hit marked coarse.
 * Both find their levels' starts after the page table (before MV_TRACE_PAGE_RUNS); MV_ENC_PAGED_SSVDAG is the
 * same for an ssvdag.
 * Other encodings ignore usage and request. */
MV_INLINE MvHit mv_trace(MvBufU32 words, MvBufU32 bricks, MvBufU32 lvl_off, MvBufU32 usage, MvBufU32 request,
                         mv_u32 enc, mv_u32 variant, MvRay r, mv_f32 start, MvTraceParams p) {
  const mv_u32 L = MV_TRACE_LEVELS(p);
  const mv_f32 proj = p.proj;
  const mv_u32 max_steps = p.max_steps;
  MvHit h = mv_miss_hit();
  mv_f32 o[3];
  mv_f32 inv[3];
  o[0] = r.ox; o[1] = r.oy; o[2] = r.oz;
  inv[0] = mv_rcp(mv_dir_clamp(r.dx));
  inv[1] = mv_rcp(mv_dir_clamp(r.dy));
  inv[2] = mv_rcp(mv_dir_clamp(r.dz));
  MvEntry e = mv_ray_entry(o[0], o[1], o[2], inv[0], inv[1], inv[2], r.tmax);
  if (L == 0u || e.enters == 0u) return h;
  mv_f32 te = e.t;
  mv_u32 ae = e.axis;
  mv_u32 top = 31u; /* the levels whose cells have ae's plane inside: above top (mv_restart) */
  if (start > 0.0f) {
    /* the finest level m whose parents' cells cannot stop the ray for its LOD by `start` */
    mv_u32 m = 0u;
    while (m + 1u < L && proj > 0.0f && mv_cell_side(m + 1u, L) * proj < start + r.lod_t) ++m;
    MvRestart rs = mv_restart(r, inv[0], inv[1], inv[2], e, start, m, L);
    if (rs.state == MV_RESTART_MISS) return h;
    te = rs.t;
    ae = rs.axis;
    top = rs.top;
  }

  /* Per node level: the node (word index; an ssvdag brick: its low half), its header (a brick: its high
   * half), its mirror mask and its full slots (see mv_node_occupancy). */
  mv_u32 node_at[22];
  mv_u32 hdr_at[22];
  mv_u32 mir_at[22];
  mv_u32 occ_at[22];
  mv_u32 nl = L;
  const mv_u32 runs_at = p.level_base[MV_TRACE_PAGE_RUNS];
  const mv_u32 starts_in_params = variant & MV_TRACE_STARTS_IN_PARAMS;
  /* paged: the levels' 64-bit starts after the page table (a word stream's pointers count from them where the
   * variant says MV_TRACE_RELATIVE, else they are absolute), and the root's stream word (its level's start; a
   * paged ssvdag's counts 16-bit words) */
  const mv_u32 levels_at = mv_enc_paged(enc) ? runs_at - 2u * (L + 1u) : 0u;
  const bool relative = enc == MV_ENC_PAGED_SSVDAG || (enc == MV_ENC_PAGED && (variant & MV_TRACE_RELATIVE) != 0u);
  const mv_u64 root_start = relative ? MV_LD_PAIR(bricks, levels_at + 2u * L) : MV_U64(0u);
  const mv_u64 root_word = enc == MV_ENC_PAGED_SSVDAG ? root_start >> 1 : root_start;
  const mv_u32 page_count = levels_at; /* paged: the pages, before the table's tail */
  /* paged: the ray's run (see MV_PAGE_STEP; none at first) and the page it last stamped */
  const mv_u32 page_shift = mv_enc_paged(enc) ? MV_TRACE_PAGE_SHIFT(p) : 0u;
  const mv_u32 stamp_usage = mv_enc_paged(enc) ? variant & MV_TRACE_STAMPS : 0u;
  mv_u64 run_lo = MV_U64(0u);
  mv_u32 run_span = 0u, run_at = 0u, last_page = MV_CACHE_NONE;
  mv_u64 left_run = MV_NO_WORD; /* whole cache: the word whose step left the run, resolved after the loop */
  mv_u32 root_at = 0u;
  if (mv_enc_paged(enc)) {
    MV_PAGE_ENTER(root_word, root_at)
  }
  mv_u32 coarse = root_at == MV_CACHE_NONE ? 1u : 0u; /* paged, root page missing: the root cube is the hit */
  root_at = coarse != 0u ? 0u : root_at;
  if (enc == MV_ENC_PAGED_SSVDAG && coarse == 0u) root_at = (root_at << 1) | MV_U32(root_start & MV_U64(1u));
  node_at[L] = root_at;
  mir_at[L] = 0u;
  mv_u64 root = mv_node_load(words, bricks, enc, L, root_at); /* ssvdag: L >= 3, inner */
  hdr_at[L] = mv_enc_compact(enc) ? mv_inner_word(root, root_at) : MV_U32(root);
  occ_at[L] = mv_node_occupancy(enc, hdr_at[L]);
  mv_u32 lc = L - 1u; /* level of the cells being walked: the children of the node */
  mv_f32 s = mv_cell_side(lc, L);
  mv_u32 idx[3];
  MV_UNROLL for (mv_u32 k = 0u; k < 3u; ++k) idx[k] = mv_child_half(0u, s, o[k], inv[k], k, te, ae, L <= top);

  mv_u32 status = MV_TRACE_MISS;
  mv_u32 steps = 0u;
  /* the step limit, or (paged) the step whose descent met a missing page: the walk leaves before the next */
  mv_u32 limit = coarse != 0u ? 0u : max_steps;
  if (coarse != 0u) /* the root's cell (a level up, after the loop) */
    MV_UNROLL for (mv_u32 k = 0u; k < 3u; ++k) idx[k] = 0u;
  for (;;) {
    for (;;) {
      /* a descent into a missing page (coarse) leaves at the next step: its one exit shared with the step limit
       * (lavapipe pays for each exit; see the hit below), and the descent is undone after the loop */
      if (steps == limit) {
        status = coarse != 0u ? MV_TRACE_HIT : MV_TRACE_GAVE_UP;
        break;
      }
      ++steps;
      mv_u32 slot = ((idx[0] & 1u) | ((idx[1] & 1u) << 1) | ((idx[2] & 1u) << 2)) ^ mir_at[nl];
      if (((occ_at[nl] >> slot) & 1u) != 0u) {
        /* a hit: a voxel or a cell small enough for the LOD. A descent into a missing page (paged) reads a
         * harmless word by selects and leaves at the next step instead of branching around the reads (lavapipe
         * keeps every branch's lane masks: each exit or guard costs it several % of the trace) */
        if (!(lc == 0u || (proj > 0.0f && s * proj < te + r.lod_t))) {
          /* descend into the child at `slot`, of level lv; every node read is an mv_node_load */
          mv_u32 t8 = mv_xmajor_octant(slot);
          mv_u32 node = node_at[nl];
          mv_u32 hdr = hdr_at[nl];
          mv_u32 lv = nl - 1u;
          if (!mv_enc_compact(enc)) {
            mv_u32 child = MV_U32(mv_node_load(words, bricks, enc, nl, mv_word_child_at(node, hdr, t8)));
            if (enc == MV_ENC_PAGED) {
              mv_u64 word = (relative ? MV_LD_PAIR(bricks, levels_at + 2u * lv) : MV_U64(0u)) + MV_U64(child);
              MV_PAGE_STEP(word, child) /* a miss reads the first slot word, then leaves: no branch */
            }
            mv_u32 child_hdr = MV_U32(mv_node_load(words, bricks, enc, lv, child));
            node_at[lv] = child;
            hdr_at[lv] = child_hdr;
            occ_at[lv] = mv_node_occupancy(enc, child_hdr);
            mir_at[lv] = mir_at[nl] ^ mv_word_child_tag(hdr, t8);
          } else { /* ssvdag: inner node -> inner node (nl > 3) or brick (nl = 3); brick -> 2^3 sub-block */
            mv_u32 tag = 0u, child = 0u, child_hdr = 0u, child_occ = 0u;
            if (nl >= 3u) {
              mv_u32 at = mv_ssvdag_child_at(node, hdr, t8);
              mv_u32 code = mv_ssvdag_child_code(hdr, t8);
              mv_u32 ptr = mv_inner_words(mv_node_load(words, bricks, enc, nl, at), at);
              mv_u32 off = mv_ssvdag_offset(ptr, code);
              tag = mv_ssvdag_tag(ptr);
              bool inner = lv > 2u;
              if (enc == MV_ENC_PAGED_SSVDAG) {
                /* the child's stream word (inner levels count 16-bit words, two per word; bricks two words each,
                 * from word 0) */
                mv_u64 start = starts_in_params == 0u ? MV_LD_PAIR(bricks, levels_at + 2u * (inner ? lv : 2u))
                               : inner ? MV_U64(mv_params_level_base(p, lv, MV_TRACE_PAGED_PARAM_LEVELS))
                                       : MV_U64(0u);
                mv_u64 w16 = start + (inner ? MV_U64(off) : MV_U64(off) * MV_U64(2u));
                mv_u64 word = inner ? w16 >> 1 : w16;
                mv_u32 at = 0u;
                MV_PAGE_STEP(word, at) /* as for the word encodings */
                child = inner ? (at << 1) | MV_U32(w16 & MV_U64(1u)) : at;
              } else {
                child = mv_level_base(p, lvl_off, lv, starts_in_params) + off;
              }
              mv_u64 data = mv_node_load(words, bricks, enc, lv, inner || enc == MV_ENC_PAGED_SSVDAG ? child : off);
              if (inner) {
                child_hdr = mv_inner_word(data, child);
                child_occ = mv_node_occupancy(enc, child_hdr);
              } else {
                child = MV_U32(data);
                child_hdr = MV_U32(data >> 32);
                child_occ = mv_brick_occupancy(child, child_hdr);
              }
            } else { /* the brick's halves; the same mirror mask */
              child_occ = mv_sub_block_occupancy(node, hdr, slot);
            }
            node_at[lv] = child;
            hdr_at[lv] = child_hdr;
            occ_at[lv] = child_occ;
            mir_at[lv] = mir_at[nl] ^ tag;
          }
          nl -= 1u;
          lc -= 1u;
          s = s * 0.5f;
          MV_UNROLL for (mv_u32 k = 0u; k < 3u; ++k)
            idx[k] = 2u * idx[k] + mv_child_half(idx[k], s, o[k], inv[k], k, te, ae, lc < top);
          continue;
        }
        status = MV_TRACE_HIT;
        break;
      }
      /* empty: step to the next cell of this level (lowest axis first on equal times) */
      mv_u32 a = 0u;
      mv_f32 ta = 0.0f;
      MV_UNROLL for (mv_u32 k = 0u; k < 3u; ++k) {
        mv_f32 t = mv_cross(MV_F32(idx[k] + (inv[k] > 0.0f ? 1u : 0u)) * s, o[k], inv[k]);
        if (k == 0u || t < ta) {
          ta = t;
          a = k;
        }
      }
      if (ta > r.tmax) break;
      te = ta;
      ae = a;
      top = 31u;
      /* idx[a] and inv[a] by selects: one index not known at compile time keeps a whole array in memory, where
       * the loop's narrow stores and wider vector loads of idx stall store forwarding (PoCL: ~13 % of the paged
       * trace's samples on one load) */
      mv_u32 old = a == 0u ? idx[0] : (a == 1u ? idx[1] : idx[2]);
      mv_f32 inv_a = a == 0u ? inv[0] : (a == 1u ? inv[1] : inv[2]);
      mv_u32 nw = inv_a > 0.0f ? old + 1u : old - 1u;
      mv_u32 j = MV_FIND_MSB(old ^ nw) + 1u; /* the node of level lc + j is the first to hold the new cell */
      if (lc + j > L) break;                 /* left the root */
      MV_UNROLL for (mv_u32 k = 0u; k < 3u; ++k)
        if (k == a) idx[k] = nw;
      if (j > 1u) {
        MV_UNROLL for (mv_u32 k = 0u; k < 3u; ++k) idx[k] = idx[k] >> (j - 1u);
        nl = lc + j;
        lc = nl - 1u;
        s = mv_cell_side(lc, L);
      }
    }
    if (coarse == 0u) break;
    /* back to the cell whose child is missing: the coarse hit (a descent keeps te and ae, and doubles s exactly) */
    nl += 1u;
    lc += 1u;
    s = s * 2.0f;
    MV_UNROLL for (mv_u32 k = 0u; k < 3u; ++k) idx[k] = idx[k] >> 1;
    /* a whole cache's walk that left its run (MV_PAGE_STEP): resolve the page, then repeat the step from its cell
     * (the same step count), or keep the coarse hit where the page is missing */
    if (left_run == MV_NO_WORD) break;
    mv_u32 at = 0u;
    MV_PAGE_ENTER(left_run, at)
    left_run = MV_NO_WORD;
    if (at == MV_CACHE_NONE) break;
    coarse = 0u;
    status = MV_TRACE_MISS;
    steps -= 1u;
    limit = max_steps;
  }
  if (mv_enc_paged(enc) && coarse != 0u) mv_page_request(request, p, last_page); /* the page it stopped at */
  h.steps = steps;
  if (status != MV_TRACE_HIT) {
    h.info = status | (MV_AXIS_NONE << 2);
    return h;
  }
  h.t = te;
  h.x = idx[0]; h.y = idx[1]; h.z = idx[2];
  mv_f32 inv_e = ae == 0u ? inv[0] : (ae == 1u ? inv[1] : inv[2]);
  mv_u32 negative = ae != MV_AXIS_NONE && inv_e > 0.0f ? 1u : 0u;
  h.info = MV_TRACE_HIT | (ae << 2) | (negative << 4) | (lc << 8) | (coarse != 0u ? MV_INFO_COARSE_BIT : 0u);
  return h;
}

#if !defined(MV_CPP)
/* One work-item's share of a trace dispatch. `enc` and `variant` are constants of the entry point, so each
 * kernel compiles only its own decode. enc: MV_ENC_SVDAG for every 32-bit word encoding, MV_ENC_PAGED for them
 * through the page cache, MV_ENC_SSVDAG, or MV_ENC_PAGED_SSVDAG. variant: MV_TRACE_STARTS_IN_PARAMS and
 * MV_TRACE_STAMPS and MV_TRACE_RELATIVE (trace_types.h). */
MV_INLINE void mv_trace_rays(MvBufF32 rays, MvBufF32 cam, MvBufU32 words, MvBufU32 bricks, MvBufU32 lvl_off,
                             MvBufU32 usage, MvBufU32 request, MvBufU32 results, MvTraceParams p, mv_u32 gid,
                             mv_u32 gsize, mv_u32 enc, mv_u32 variant) {
  MvItems r = mv_items(p.block, gid, gsize, p.count);
  for (mv_u32 j = r.begin; j < r.end; j += r.step) {
    mv_u32 i = p.first + j;
    /* camera rays with the beam pre-pass: the start of the ray's tile, after the camera record (trace_beam.h) */
    mv_f32 start =
        MV_TRACE_BEAM(p) == 1u ? MV_LD(cam, MV_CAMERA_FLOATS + mv_beam_tile(mv_camera_pixel(cam, i), p.width)) : 0.0f;
    MvHit h = mv_miss_hit(); /* a tile that sees nothing: the walk's miss, without making the ray */
    if (start < MV_BEAM_NOTHING)
      h = mv_trace(words, bricks, lvl_off, usage, request, enc, variant, mv_trace_source_ray(rays, cam, i, p), start, p);
    if (MV_TRACE_OCCLUSION(p) == 1u) {
      if (MV_INFO_STATUS(h.info) == MV_TRACE_HIT) MV_ST(results, i, MV_LD(results, i) + 1u);
    } else {
      mv_store_hit(results, i, h);
    }
  }
}
#endif

#endif /* MV_TRACE_H */