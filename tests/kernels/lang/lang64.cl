// OpenCL entry points of the language-layer probes, 64-bit atomics (bodies: bodies/lang_probe.h).
#define MV_LANG64 1
#include "../bodies/lang_probe.h"
#include "../bodies/lang_shared_atomics.h"

__kernel void lang_atomics_k64(__global ulong* vals, __global ulong* slots, __global ulong* olds, MvLangParams p) {
  uint i = MV_GLOBAL_ID();
  if (i < p.n) mv_lang_atomics(vals, slots, olds, i);
}

__kernel void lang_shared_atomics_k64(__global ulong* vals, __global ulong* out, MvLangParams p) {
  MV_SHARED(ulong, cells, MV_LANG_CELLS);
  mv_lang_shared_atomics(MV_SHARED_ARG(cells) vals, out, p.n);
}
