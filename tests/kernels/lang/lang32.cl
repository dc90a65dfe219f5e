// OpenCL entry points of the language-layer probes, 32-bit (bodies: bodies/lang_probe.h).
#include "../bodies/lang_probe.h"
#include "../bodies/lang_shared_atomics.h"
#include "../bodies/lang_histogram.h"

__kernel void lang_atomics_k32(__global uint* vals, __global uint* slots, __global uint* olds, MvLangParams p) {
  uint i = MV_GLOBAL_ID();
  if (i < p.n) mv_lang_atomics(vals, slots, olds, i);
}

__kernel void lang_shared_atomics_k32(__global uint* vals, __global uint* out, MvLangParams p) {
  MV_SHARED(uint, cells, MV_LANG_CELLS);
  mv_lang_shared_atomics(MV_SHARED_ARG(cells) vals, out, p.n);
}

__kernel void lang_histogram(__global uint* keys, __global uint* hist, MvLangParams p) {
  MV_SHARED(uint, bins, MV_LANG_BINS);
  mv_lang_histogram(MV_SHARED_ARG(bins) keys, hist, p.n);
}

__kernel void lang_grid2d(__global uint* out, MvLangParams p) { mv_lang_grid2d(out, p.width, p.height); }

__kernel void lang_args(__global uint* out, __global uint* a, __global uint* b, __global uint* c, __global uint* d,
                        __global uint* e, MvLangArgsParams p) {
  if (MV_GLOBAL_ID() == 0u) mv_lang_args(out, a, b, c, d, e, p);
}
