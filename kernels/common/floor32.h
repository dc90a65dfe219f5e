/* floor and ceil of a float from a conversion and a compare, written once for the host, OpenCL C and GLSL. PoCL
 * compiles them to software sequences (no rounding instruction); the traversal's restarts place a ray on a
 * level's planes with them (secondary rays restart most: 5-14 % faster with these). Exact for every float: past
 * 2^23 every float is an integer, and NaN stays NaN. Apart from floor64.h so that float-only kernels need no
 * double support. */
#ifndef MV_FLOOR32_H
#define MV_FLOOR32_H
#include "mv_lang.h"

MV_INLINE mv_f32 mv_floor32(mv_f32 x) {
  if (!(x > -8388608.0f && x < 8388608.0f)) return x;
  mv_f32 t = MV_F32(MV_I32(x));
  return t > x ? t - 1.0f : t;
}

MV_INLINE mv_f32 mv_ceil32(mv_f32 x) {
  if (!(x > -8388608.0f && x < 8388608.0f)) return x;
  mv_f32 t = MV_F32(MV_I32(x));
  return t < x ? t + 1.0f : t;
}

#endif /* MV_FLOOR32_H */
