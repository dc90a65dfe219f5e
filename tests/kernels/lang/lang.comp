// Vulkan entry points of the language-layer probes, one module per -DMV_ENTRY_<name>; MV_LANG64 picks 64-bit
// elements (bodies: bodies/lang_probe.h).
#version 460
#extension GL_GOOGLE_include_directive : require
#include "common/mv_glsl_prelude.h"
#include "../bodies/lang_probe.h"

#if defined(MV_ENTRY_atomics)
MV_ARGS(MvLangBuf vals; MvLangBuf slots; MvLangBuf olds; MvLangParams p;);
void main() {
  uint i = MV_GLOBAL_ID();
  if (i < args.p.n) mv_lang_atomics(args.vals, args.slots, args.olds, i);
}
#elif defined(MV_ENTRY_shared_atomics)
MV_SHARED(MvLangT, cells, MV_LANG_CELLS);
#include "../bodies/lang_shared_atomics.h"
MV_ARGS(MvLangBuf vals; MvLangBuf out_; MvLangParams p;);
void main() { mv_lang_shared_atomics(MV_SHARED_ARG(cells) args.vals, args.out_, args.p.n); }
#elif defined(MV_ENTRY_histogram)
MV_SHARED(uint, bins, MV_LANG_BINS);
#include "../bodies/lang_histogram.h"
MV_ARGS(MvBufU32 keys; MvBufU32 hist; MvLangParams p;);
void main() { mv_lang_histogram(MV_SHARED_ARG(bins) args.keys, args.hist, args.p.n); }
#elif defined(MV_ENTRY_grid2d)
MV_ARGS(MvBufU32 out_; MvLangParams p;);
void main() { mv_lang_grid2d(args.out_, args.p.width, args.p.height); }
#elif defined(MV_ENTRY_args)
MV_ARGS(MvBufU32 out_; MvBufU32 a; MvBufU32 b; MvBufU32 c; MvBufU32 d; MvBufU32 e; MvLangArgsParams p;);
void main() {
  if (MV_GLOBAL_ID() == 0u) mv_lang_args(args.out_, args.a, args.b, args.c, args.d, args.e, args.p);
}
#else
#error "define MV_ENTRY_atomics, shared_atomics, histogram, grid2d or args"
#endif
