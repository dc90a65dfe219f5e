/* The beam pre-pass of camera rays (ESVO's beam optimization, made exact), written once for the host, OpenCL C
 * and GLSL. A frame's pixels are taken in tiles of MV_BEAM_TILE^2; for each tile a coarse pass finds a t before
 * which none of its rays can meet a full cell, and each ray then starts its walk there (mv_restart) instead of
 * at the root cube's face: the same hit in fewer steps, and a tile that sees only empty space does no walk.
 * The tiles' pass starts from a first pass over tiles twice as wide (on a coarser grid, as their rays stray
 * further): a parent's start holds for its four tiles, so theirs walk only on from there.
 *
 * The proof uses a coarse grid of G^3 cells (cell side S = 1/G of the root cube): a cell is full when the DAG
 * has anything in it (the trace kernel itself answers, one ray per cell: see TraceEngine::beam), and the grid is
 * dilated by one cell (a cell is marked when it or any of its 26 neighbours is full), with a border of one cell
 * outside the cube. A tile's centre ray walks the dilated grid (a plain float DDA) to the first marked cell.
 * Every ray of the tile stays within t * reach of the centre ray on each axis (reach: from the camera's pixel
 * steps, host-made), so while t * reach <= S / 2 its point lies within S / 2 of a cell the centre ray visited,
 * that is in the cell or a neighbour: empty. The other S / 2 covers the DDA's rounding. Cells coarser than S can
 * stop a ray for its level of detail without a voxel near it, so the start is also held below the t at which
 * a cell of side 2S would (lod_limit). */
#ifndef MV_TRACE_BEAM_H
#define MV_TRACE_BEAM_H
#include "trace_ray.h"

MV_STRUCT_BEGIN(MvBeamParams)
  mv_u32 first;       /* items [first, first + count) in this dispatch: grid words or tiles */
  mv_u32 count;
  mv_u32 cells;       /* G, the coarse grid's cells per axis (a power of two) */
  mv_u32 width;       /* the frame in pixels (beam_starts) */
  mv_u32 height;
  mv_f32 reach;       /* a tile's rays stray at most t * reach from its centre ray, on each axis */
  mv_f32 lod_limit;   /* a start is held below this t (see above) */
  mv_u32 block;       /* nonzero: each work-item takes this many consecutive items (CPU devices) */
  mv_u32 tile;        /* beam_starts: pixels per tile side */
  mv_u32 at;          /* beam_starts: tile j's start goes to cam[MV_CAMERA_FLOATS + at + j] */
  mv_u32 parent_at;   /* beam_starts: where the starts of tiles twice as wide are, or MV_BEAM_NO_PARENT */
  mv_u32 pad;
MV_STRUCT_END(MvBeamParams)
#define MV_BEAM_NO_PARENT 0xffffffffu
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvBeamParams, 48);
MV_LAYOUT_AT(MvBeamParams, first, 0); MV_LAYOUT_AT(MvBeamParams, count, 4); MV_LAYOUT_AT(MvBeamParams, cells, 8);
MV_LAYOUT_AT(MvBeamParams, width, 12); MV_LAYOUT_AT(MvBeamParams, height, 16); MV_LAYOUT_AT(MvBeamParams, reach, 20);
MV_LAYOUT_AT(MvBeamParams, lod_limit, 24); MV_LAYOUT_AT(MvBeamParams, block, 28); MV_LAYOUT_AT(MvBeamParams, tile, 32);
MV_LAYOUT_AT(MvBeamParams, at, 36); MV_LAYOUT_AT(MvBeamParams, parent_at, 40); MV_LAYOUT_AT(MvBeamParams, pad, 44);
#endif

/* The grids' layout: rows of bits along x, a row per (y, z) (row z * n + y for n cells per axis), each row
 * whole 32-bit words, bit x & 31 of word x >> 5. The full-cell grid has n = G; the dilated one n = G + 2, its
 * cell (x, y, z) the coarse cell (x - 1, y - 1, z - 1). */
MV_INLINE mv_u32 mv_beam_row_words(mv_u32 n) { return (n + 31u) / 32u; }

/* Full-cell grid word j: bit b is cell (32 x-word + b, y, z) and is set where that cell's trace hit (`counts`:
 * the occlusion counts of one ray per cell, x fastest). */
MV_INLINE void mv_beam_pack(MvBufU32 counts, MvBufU32 full, MvBeamParams p, mv_u32 gid, mv_u32 gsize) {
  const mv_u32 g = p.cells;
  const mv_u32 rw = mv_beam_row_words(g);
  MvItems r = mv_items(p.block, gid, gsize, p.count);
  for (mv_u32 i = r.begin; i < r.end; i += r.step) {
    mv_u32 j = p.first + i;
    mv_u32 row = j / rw;
    mv_u32 x0 = (j % rw) * 32u;
    mv_u32 bits = 0u;
    for (mv_u32 b = 0u; b < 32u && x0 + b < g; ++b)
      if (MV_LD(counts, row * g + x0 + b) != 0u) bits |= 1u << b;
    MV_ST(full, j, bits);
  }
}

/* Word `w` - 2 of a full-cell grid row (0 outside the row). */
MV_INLINE mv_u32 mv_beam_word(MvBufU32 full, mv_u32 row, mv_u32 w, mv_u32 rw) {
  return w >= 2u && w - 2u < rw ? MV_LD(full, row * rw + w - 2u) : 0u;
}

/* 32 bits of a full-cell grid row from cell x = x64 - 64 on (x may be negative: those cells are empty). */
MV_INLINE mv_u32 mv_beam_window(MvBufU32 full, mv_u32 row, mv_u32 x64, mv_u32 rw) {
  mv_u32 w = x64 >> 5;
  mv_u32 sh = x64 & 31u;
  mv_u32 lo = mv_beam_word(full, row, w, rw);
  mv_u32 hi = mv_beam_word(full, row, w + 1u, rw);
  return sh == 0u ? lo : (lo >> sh) | (hi << (32u - sh));
}

/* Dilated grid word j: a cell is marked where any of the 27 full-cell grid cells around it is full. */
MV_INLINE void mv_beam_dilate(MvBufU32 full, MvBufU32 marked, MvBeamParams p, mv_u32 gid, mv_u32 gsize) {
  const mv_u32 g = p.cells;
  const mv_u32 n = g + 2u;
  const mv_u32 rw = mv_beam_row_words(g);
  const mv_u32 rn = mv_beam_row_words(n);
  MvItems r = mv_items(p.block, gid, gsize, p.count);
  for (mv_u32 i = r.begin; i < r.end; i += r.step) {
    mv_u32 j = p.first + i;
    mv_u32 row = j / rn;
    mv_u32 x0 = (j % rn) * 32u; /* the word's first dilated x: coarse x0 - 1, whose neighbours start at x0 - 2 */
    mv_u32 ye = row % n, ze = row / n;
    mv_u32 bits = 0u;
    for (mv_u32 dz = 0u; dz < 3u; ++dz)
      for (mv_u32 dy = 0u; dy < 3u; ++dy) {
        /* coarse y = ye - 2 + dy, z = ze - 2 + dz, inside [0, g) */
        if (ye + dy < 2u || ye + dy - 2u >= g || ze + dz < 2u || ze + dz - 2u >= g) continue;
        mv_u32 src = (ze + dz - 2u) * g + (ye + dy - 2u);
        bits |= mv_beam_window(full, src, x0 + 62u, rw) | mv_beam_window(full, src, x0 + 63u, rw) |
                mv_beam_window(full, src, x0 + 64u, rw);
      }
    MV_ST(marked, j, bits);
  }
}

/* Is dilated cell (x, y, z) marked? */
MV_INLINE bool mv_beam_marked(MvBufU32 marked, mv_u32 n, mv_u32 x, mv_u32 y, mv_u32 z) {
  return ((MV_LD(marked, (z * n + y) * mv_beam_row_words(n) + (x >> 5)) >> (x & 31u)) & 1u) != 0u;
}

/* Tile j's start: written after the camera record, at cam[MV_CAMERA_FLOATS + p.at + j] (mv_trace_rays reads the
 * final pass's, p.at = 0, there). With a parent pass, the walk goes on from the parent tile's start. */
MV_INLINE void mv_beam_starts(MvBufU32 marked, MvBufU32 cam, MvBeamParams p, mv_u32 gid, mv_u32 gsize) {
  const mv_u32 g = p.cells;
  const mv_u32 n = g + 2u;
  const mv_f32 fg = MV_F32(g);
  const mv_f32 fn = MV_F32(n);
  const mv_u32 tile = p.tile;
  const mv_u32 tiles_x = (p.width + tile - 1u) / tile;
  MvItems r = mv_items(p.block, gid, gsize, p.count);
  for (mv_u32 i = r.begin; i < r.end; i += r.step) {
    mv_u32 j = p.first + i;
    mv_u32 x0 = (j % tiles_x) * tile, y0 = (j / tiles_x) * tile;
    /* no ray of the parent tile, a superset of this one's, meets a full cell before t0 */
    mv_f32 t0 = 0.0f;
    if (p.parent_at != MV_BEAM_NO_PARENT) {
      mv_u32 pt = 2u * tile;
      t0 = MV_BITSF(MV_LD(cam, MV_CAMERA_FLOATS + p.parent_at + (y0 / pt) * ((p.width + pt - 1u) / pt) + x0 / pt));
    }
    if (t0 >= MV_BEAM_NOTHING) {
      MV_ST(cam, MV_CAMERA_FLOATS + p.at + j, MV_FBITS(MV_BEAM_NOTHING));
      continue;
    }
    mv_f32 cx = 0.5f * MV_F32(x0 + MV_MIN(x0 + tile, p.width) - 1u);
    mv_f32 cy = 0.5f * MV_F32(y0 + MV_MIN(y0 + tile, p.height) - 1u);
    /* the centre ray in dilated-grid units: q(t) = (eye + t d) G + 1 */
    mv_f32 q[3];
    mv_f32 v[3];
    mv_f32 inv[3];
    mv_f32 t_in = 0.0f, t_out = 1e30f;
    mv_f32 v_out = 0.0f; /* the centre ray's speed on the axis it leaves the dilated grid by */
    for (mv_u32 k = 0u; k < 3u; ++k) {
      mv_f32 d = MV_BITSF(MV_LD(cam, MV_CAMERA_BASE + k)) + cx * MV_BITSF(MV_LD(cam, MV_CAMERA_DU + k)) +
                 cy * MV_BITSF(MV_LD(cam, MV_CAMERA_DV + k));
      q[k] = MV_BITSF(MV_LD(cam, MV_CAMERA_EYE + k)) * fg + 1.0f;
      v[k] = mv_dir_clamp(d * fg);
      inv[k] = 1.0f / v[k];
      mv_f32 ta = (0.0f - q[k]) * inv[k], tb = (fn - q[k]) * inv[k];
      t_in = MV_MAX(t_in, MV_MIN(ta, tb));
      v_out = MV_MAX(ta, tb) < t_out ? v[k] : v_out;
      t_out = MV_MIN(t_out, MV_MAX(ta, tb));
    }
    t_in = MV_MAX(t_in, t0);
    mv_f32 hit = 1e30f; /* where the centre ray enters its first marked cell from t0 on */
    bool left = t_in >= t_out; /* it left the dilated grid (or never met it) without meeting one */
    if (t_in < t_out) {
      mv_u32 c[3];
      mv_f32 next[3];
      for (mv_u32 k = 0u; k < 3u; ++k) {
        mv_f32 at = mv_floor32(q[k] + t_in * v[k]);
        c[k] = at < 0.0f ? 0u : (at > fn - 1.0f ? n - 1u : MV_U32(at));
        next[k] = (MV_F32(c[k] + (v[k] > 0.0f ? 1u : 0u)) - q[k]) * inv[k];
      }
      mv_f32 t = t_in;
      for (mv_u32 step = 0u; step < 3u * n + 3u; ++step) {
        if (mv_beam_marked(marked, n, c[0], c[1], c[2])) {
          hit = t;
          break;
        }
        mv_u32 a = next[1] < next[0] ? 1u : 0u;
        a = next[2] < (a == 0u ? next[0] : next[1]) ? 2u : a;
        t = a == 0u ? next[0] : (a == 1u ? next[1] : next[2]);
        bool up = (a == 0u ? v[0] : (a == 1u ? v[1] : v[2])) > 0.0f;
        mv_u32 ca = a == 0u ? c[0] : (a == 1u ? c[1] : c[2]);
        if (t >= t_out || (!up && ca == 0u) || (up && ca + 1u >= n)) {
          left = true;
          break;
        }
        ca = up ? ca + 1u : ca - 1u;
        mv_f32 span = (up ? 1.0f : -1.0f) * (a == 0u ? inv[0] : (a == 1u ? inv[1] : inv[2]));
        for (mv_u32 k = 0u; k < 3u; ++k)
          if (k == a) {
            c[k] = ca;
            next[k] = next[k] + span;
          }
      }
    }
    mv_f32 reach = 0.5f / (p.reach * fg);
    mv_f32 start = MV_MAX(t0, MV_MIN(MV_MIN(hit, reach), p.lod_limit) * (1.0f - 1.0f / 1024.0f));
    /* Left the dilated grid within reach, faster than the tile's rays stray: until then every ray of the tile
     * was outside the cube or in empty cells, and from then on each is outside the cube by S / 2 or more on
     * that axis, moving away. */
    if (left && t_out <= reach && (v_out < 0.0f ? -v_out : v_out) > 2.0f * p.reach * fg) start = MV_BEAM_NOTHING;
    MV_ST(cam, MV_CAMERA_FLOATS + p.at + j, MV_FBITS(start));
  }
}

#endif /* MV_TRACE_BEAM_H */
