/* floor of a double from a conversion and a compare, written once for the host, OpenCL C and GLSL. PoCL compiles
 * floor(double) to a software sequence (no rounding instruction): it was the costliest step of a mesh's texture
 * lookups, and a sixth of GrabCut's data terms. Exact for every double: past 2^52 every double is an integer,
 * and NaN stays NaN. */
#ifndef MV_FLOOR64_H
#define MV_FLOOR64_H
#include "mv_lang.h"

MV_INLINE mv_f64 mv_floor64(mv_f64 x) {
  if (!(x > -4503599627370496.0 && x < 4503599627370496.0)) return x;
  mv_f64 t = MV_F64(MV_I64(x));
  return t > x ? t - 1.0 : t;
}

#endif /* MV_FLOOR64_H */
