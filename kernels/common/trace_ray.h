/* Ray setup and the exact crossing arithmetic of traversal (trace.h), written once for the host, OpenCL C and
 * GLSL: a deterministic reciprocal, crossing times, the (t, axis) order of events, which child half a ray is
 * in, and where it enters the root cube. Apart from the loop: this is the arithmetic every device must agree
 * on bit for bit (trace.h says why that makes every walk the same). */
#ifndef MV_TRACE_RAY_H
#define MV_TRACE_RAY_H
#include "floor32.h"
#include "trace_types.h"

/* 1 / x for |x| in [1e-20, 1e20], identical on every device (not always correctly rounded). */
MV_INLINE mv_f32 mv_rcp(mv_f32 x) {
  mv_u32 b = MV_FBITS(x);
  MV_PRECISE mv_f32 a = MV_BITSF(b & 0x7fffffffu);
  MV_PRECISE mv_f32 r = MV_BITSF(0x7ef311c3u - (b & 0x7fffffffu));
  r = r * (2.0f - a * r);
  r = r * (2.0f - a * r);
  r = r * (2.0f - a * r);
  r = r * (2.0f - a * r);
  return MV_BITSF(MV_FBITS(r) | (b & 0x80000000u));
}

/* Direction components keep their sign (zero counts as positive) and at least 1e-20 magnitude. */
MV_INLINE mv_f32 mv_dir_clamp(mv_f32 d) {
  if (d >= 0.0f && d < 1e-20f) return 1e-20f;
  if (d < 0.0f && d > -1e-20f) return -1e-20f;
  return d;
}

/* The side of a cell of level l in a root cube of level L: 2^(l - L), exact. */
MV_INLINE mv_f32 mv_cell_side(mv_u32 l, mv_u32 L) { return MV_BITSF(((127u + l) - L) << 23); }

MV_INLINE mv_f32 mv_cross(mv_f32 b, mv_f32 o, mv_f32 inv) {
  MV_PRECISE mv_f32 t = (b - o) * inv;
  return t;
}

/* Event (t, k) comes strictly before event (te, ae). */
MV_INLINE bool mv_before(mv_f32 t, mv_u32 k, mv_f32 te, mv_u32 ae) { return t < te || (t == te && k < ae); }

/* Has the crossing (t, k) happened by event (te, ae)? The start event of a ray that begins inside the cube
 * (ae = MV_AXIS_NONE, te = 0) counts only crossings at t < 0: a ray starting on a boundary is still in the
 * cell behind it and crosses at t = 0 (for both directions, so the rule does not depend on the sign of 0). */
MV_INLINE bool mv_crossed(mv_f32 t, mv_u32 k, mv_f32 te, mv_u32 ae) {
  return ae == MV_AXIS_NONE ? t < te : mv_before(t, k, te, ae);
}

/* The half (0 lower, 1 upper) along axis k of the cell of side s the ray is in, inside parent cell `parent`
 * (side 2s), given the event (te, ae): the crossing that brought it into the parent (`face`: ae's plane is the
 * parent's face, so the ray is in the half beside it), or one inside the parent (a restarted walk, mv_restart:
 * the ray has crossed ae's plane itself, so the half is the one after it). */
MV_INLINE mv_u32 mv_child_half(mv_u32 parent, mv_f32 s, mv_f32 o, mv_f32 inv, mv_u32 k, mv_f32 te, mv_u32 ae,
                               bool face) {
  MV_PRECISE mv_f32 mid = MV_F32(2u * parent + 1u) * s;
  bool pos = inv > 0.0f;
  if (k == ae && face) return pos ? 0u : 1u;
  mv_f32 t = mv_cross(mid, o, inv);
  bool crossed = k == ae ? t <= te : mv_crossed(t, k, te, ae);
  return pos == crossed ? 1u : 0u;
}

/* Where a ray enters the root cube: the event (t, axis), axis MV_AXIS_NONE when it starts inside (t = 0).
 * enters = 0 when it misses the cube or enters after tmax. exit: the t of its first far-face crossing. */
MV_STRUCT_BEGIN(MvEntry)
  mv_f32 t;
  mv_u32 axis;
  mv_u32 enters;
  mv_f32 exit;
MV_STRUCT_END(MvEntry)

/* Is the ray inside [0, 1) on this axis just before t = 0 (see mv_crossed)? */
MV_INLINE bool mv_inside_unit(mv_f32 x, mv_f32 inv) { return inv > 0.0f ? x > 0.0f && x <= 1.0f : x >= 0.0f && x < 1.0f; }

MV_INLINE MvEntry mv_ray_entry(mv_f32 o0, mv_f32 o1, mv_f32 o2, mv_f32 i0, mv_f32 i1, mv_f32 i2, mv_f32 tmax) {
  MvEntry e;
  e.t = 0.0f;
  e.axis = MV_AXIS_NONE;
  e.enters = tmax >= 0.0f ? 1u : 0u;
  mv_f32 o[3];
  mv_f32 inv[3];
  o[0] = o0; o[1] = o1; o[2] = o2;
  inv[0] = i0; inv[1] = i1; inv[2] = i2;
  mv_u32 exit_axis = MV_AXIS_NONE; /* the first far-face crossing, by (t, axis) */
  e.exit = 0.0f;
  MV_UNROLL for (mv_u32 k = 0u; k < 3u; ++k) {
    mv_f32 t = mv_cross(inv[k] > 0.0f ? 1.0f : 0.0f, o[k], inv[k]);
    if (exit_axis == MV_AXIS_NONE || mv_before(t, k, e.exit, exit_axis)) {
      e.exit = t;
      exit_axis = k;
    }
  }
  if (mv_inside_unit(o0, i0) && mv_inside_unit(o1, i1) && mv_inside_unit(o2, i2)) return e;
  MV_UNROLL for (mv_u32 k = 0u; k < 3u; ++k) {
    if (mv_inside_unit(o[k], inv[k])) continue;
    bool pos = inv[k] > 0.0f;
    if (pos ? o[k] > 1.0f : o[k] < 0.0f) e.enters = 0u; /* outside on k and moving away */
    mv_f32 t = mv_cross(pos ? 0.0f : 1.0f, o[k], inv[k]);
    if (e.axis == MV_AXIS_NONE || mv_before(e.t, e.axis, t, k)) {
      e.t = t;
      e.axis = k;
    }
  }
  if (mv_before(e.exit, exit_axis, e.t, e.axis)) e.enters = 0u; /* it leaves on one axis before it enters */
  if (e.t > tmax) e.enters = 0u;
  return e;
}

/* A walk restarted inside the cube at t = `start`, where no event at t <= start is a hit (the beam pre-pass
 * proves it for camera rays: trace_beam.h). It starts at a real event of the ray's walk: the latest (by (t,
 * axis)) crossing at or before `start` of a plane between cells of level m, where cells above level m cannot
 * stop the ray for its level of detail by then (see mv_trace). Descending from the root at that event gives the
 * cell the full walk is in after it: above `top` (the coarsest level whose cells the plane bounds) the plane
 * lies inside the cells, below it is their face (mv_child_half's `face`). */
#define MV_RESTART_NONE 0u /* walk from the entry */
#define MV_RESTART_AT 1u   /* descend from the root at (t, axis) */
#define MV_RESTART_MISS 2u /* the ray leaves the cube by `start`: nothing to walk */
MV_STRUCT_BEGIN(MvRestart)
  mv_f32 t;
  mv_u32 axis;
  mv_u32 top;
  mv_u32 state;
MV_STRUCT_END(MvRestart)

MV_INLINE MvRestart mv_restart(MvRay r, mv_f32 i0, mv_f32 i1, mv_f32 i2, MvEntry e, mv_f32 start, mv_u32 m,
                               mv_u32 L) {
  MvRestart x;
  x.t = e.t;
  x.axis = e.axis;
  x.top = 31u;
  x.state = MV_RESTART_NONE;
  mv_f32 o[3];
  mv_f32 d[3];
  mv_f32 inv[3];
  o[0] = r.ox; o[1] = r.oy; o[2] = r.oz;
  d[0] = r.dx; d[1] = r.dy; d[2] = r.dz;
  inv[0] = i0; inv[1] = i1; inv[2] = i2;
  if (e.exit <= start) {
    x.state = MV_RESTART_MISS;
    return x;
  }
  const mv_f32 planes = MV_F32(1u << (L - m)); /* level m's planes per axis: 0 .. planes */
  const mv_f32 side = mv_cell_side(m, L);
  mv_f32 best_q = 0.0f;
  bool found = false;
  MV_UNROLL for (mv_u32 k = 0u; k < 3u; ++k) {
    /* the plane behind the ray's position at `start` (any rounding there is caught by the check on t) */
    bool pos = inv[k] > 0.0f;
    MV_PRECISE mv_f32 at = (o[k] + start * d[k]) * planes;
    mv_f32 q = pos ? mv_floor32(at) : mv_ceil32(at);
    q = q < 0.0f ? 0.0f : (q > planes ? planes : q);
    mv_f32 t = mv_cross(q * side, o[k], inv[k]);
    if (t > start) {
      q = pos ? q - 1.0f : q + 1.0f;
      t = mv_cross(q * side, o[k], inv[k]);
    }
    if (t > start || q < 0.0f || q > planes) continue;
    if (!found || mv_before(x.t, x.axis, t, k)) {
      x.t = t;
      x.axis = k;
      best_q = q;
      found = true;
    }
  }
  /* only an event after the entry (a near face's crossing is not one) */
  if (!found || best_q <= 0.0f || best_q >= planes || !mv_before(e.t, e.axis, x.t, x.axis)) {
    x.t = e.t;
    x.axis = e.axis;
    return x;
  }
  x.top = m + MV_FIND_LSB(MV_U32(best_q));
  x.state = MV_RESTART_AT;
  return x;
}

#endif /* MV_TRACE_RAY_H */
