/* LSD radix sort, block-per-work-item variant (the fast shape on CPU devices: PoCL, lavapipe).
 *
 * The keys are cut into `blocks` contiguous blocks of `block_size`; work-item b owns block b. One pass
 * per 8-bit digit over the bits that vary (reduce-then-scan, no cross-work-group waiting):
 *   1. radix_histogram: each block counts its digits into hist[digit * blocks + b]
 *   2. scan_small:      exclusive scan of hist (digit-major, so offsets follow key order: stable)
 *   3. radix_scatter:   each block walks its keys in order and writes each to hist[digit][b]++
 * Before the passes radix_or_and reduces OR and AND of all keys: bits where they agree are constant over
 * every key, and the digits are laid over the varying bits only (a digit starts at any bit).
 *
 * CPU devices use a hybrid instead when the keys spread well: one such global pass on the most significant
 * varying digit, then radix_local_sort sorts each of the 256 buckets in cache (see radix_sort_body.h). */
#ifndef MV_RADIX_SORT_H
#define MV_RADIX_SORT_H
#include "mv_lang.h"

#define MV_RADIX_BITS 8
#define MV_RADIX_BUCKETS 256
#define MV_RADIX_LINE 16  /* entries per line buffer of the streaming scatter (a power of two) */
#define MV_RADIX_SMALL 32 /* in-bucket ranges of at most this many keys are finished by insertion sort */

/* The work-group-cooperative variant (radix_coop_*.h): work-groups of MV_COOP_WG items; each takes blocks of
 * MV_COOP_BLOCK keys, in tiles of MV_COOP_TILE = MV_COOP_WG x MV_COOP_ITEMS keys ranked in shared memory. */
#define MV_COOP_WG 128
#define MV_COOP_ITEMS 8
#define MV_COOP_TILE 1024
#define MV_COOP_BLOCK 8192
#define MV_COOP_NIBBLES 16                 /* a digit is ranked as two 4-bit sub-digits */
#define MV_COOP_COUNTERS (MV_COOP_NIBBLES * MV_COOP_WG)
#define MV_COOP_AUX (3 * MV_RADIX_BUCKETS + MV_COOP_WG) /* first, end and base per digit; the scan's partials */

MV_STRUCT_BEGIN(MvRadixParams)
  mv_u32 n;          /* number of keys */
  mv_u32 blocks;     /* number of blocks (= work-items doing useful work) */
  mv_u32 block_size; /* keys per block (the last block may be short) */
  mv_u32 shift;      /* lowest bit of this pass's 8-bit digit (any bit: digits need not be byte-aligned) */
  mv_u32 has_values; /* nonzero: move 32-bit values along with the keys */
  mv_u32 count;      /* radix_or_and: nonzero = also count the digit at `shift` */
  mv_u32 local_top;  /* radix_local_sort: sort the bits below this one ... */
  mv_u32 local_low;  /* ... down to this one (the lowest varying bit) */
  mv_u32 scratch_stride; /* radix_local_sort: keys per work-item scratch slice; 0 = each bucket's own range */
  mv_u32 bucket_first;   /* radix_local_sort: the buckets [bucket_first, bucket_end) of the top digit */
  mv_u32 bucket_end;
MV_STRUCT_END(MvRadixParams)
#if defined(MV_CPP)
MV_LAYOUT_SIZE(MvRadixParams, 44);
MV_LAYOUT_AT(MvRadixParams, n, 0); MV_LAYOUT_AT(MvRadixParams, blocks, 4); MV_LAYOUT_AT(MvRadixParams, block_size, 8);
MV_LAYOUT_AT(MvRadixParams, shift, 12); MV_LAYOUT_AT(MvRadixParams, has_values, 16);
MV_LAYOUT_AT(MvRadixParams, count, 20); MV_LAYOUT_AT(MvRadixParams, local_top, 24);
MV_LAYOUT_AT(MvRadixParams, local_low, 28); MV_LAYOUT_AT(MvRadixParams, scratch_stride, 32);
MV_LAYOUT_AT(MvRadixParams, bucket_first, 36); MV_LAYOUT_AT(MvRadixParams, bucket_end, 40);
#endif

#endif
