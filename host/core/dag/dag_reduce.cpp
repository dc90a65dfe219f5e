// DAG reduction of one level on the device: level 1 by ranking its 8-bit masks, level 2 by grouping its
// exact 64-bit bricks, the levels above by hashing and verifying (kernels: kernels/common/dag.h, ssvdag.h);
// with symmetry, up to reflections. Shared by the in-core build and the out-of-core merge.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "primitives/launch_shape.h"
#include "primitives/scan_plan.h"
#include "dag_build_steps.h"
#include "megavox/error.h"
#include "megavox/primitives.h"

namespace mv::detail {

namespace {

// Canonical form, T*, stabilizer and tag row of every 8-bit mask (kernel leaf_table).
Buffer mask_table(Device& dev) {
  Buffer table = dev.alloc(MV_MASK_TABLE_WORDS * 4, "mask table");
  dev.dispatch(dev.kernel(KernelId::leaf_table), dev.groups_for(256, kLocal), kLocal, {&table},
               MvDagParams{256, 0, 0, 0, 0, 0});
  dev.barrier();
  return table;
}

// Level 1: classes are (canonical) masks, ranked without hashing (kernels: leaf_table, leaf_present,
// leaf_classes); nothing is written per node.
void reduce_leaves(Device& dev, const SvoLevel& lv, Reduced& r, const Reduction& red) {
  const bool symmetric = red.symmetric;
  const Buffer& table = red.mask_table;
  MvDagParams p{lv.n, symmetric ? 2u : 1u, 0, 0, 0, 0};
  Buffer& present = r.class_rank;
  present = dev.alloc(257 * 4, "leaf classes");
  dev.fill(present, 0, 257 * 4);
  dev.barrier();
  const uint32_t groups = dev.groups_for(lv.n, kLocal);
  dev.dispatch(dev.kernel(KernelId::leaf_present), groups, kLocal, {&lv.mask, &table, &present}, p);
  dev.barrier();
  exclusive_scan(dev, present, present, 256);
  dev.download(present, &r.distinct, 4, 256 * 4);
  r.class_mask = dev.alloc(uint64_t{r.distinct} * 4, "leaf class masks");
  dev.dispatch(dev.kernel(KernelId::leaf_classes), dev.groups_for(256, kLocal), kLocal, {&present, &r.class_mask}, p);
  dev.barrier();
}

// Equal keys grouped: sort (keys, order), mark runs, rank them: id per item, the first item of each run as
// its representative; returns the number of runs. `class_keys`, when given, gets each run's key, in id order.
uint32_t group_keys(Device& dev, Buffer& keys, Buffer& order, uint32_t n, Buffer& id, Buffer& rep,
                    std::vector<uint64_t>* class_keys = nullptr) {
  Buffer run = dev.alloc((uint64_t{n} + 1) * 4, "key runs");
  const uint32_t groups = dev.groups_for(n, kLocal);
  const MvDagParams p{n, 0, 0, 0, 0, 0};
  radix_sort(dev, keys, &order, n, KeyBits::k64);
  dev.dispatch(dev.kernel(KernelId::dag_runs), groups, kLocal, {&keys, &run}, p);
  dev.barrier();
  ScanPlan scan = plan_scan(dev, n);
  record_scan(dev, scan, run, run);
  uint32_t distinct = 0;
  dev.download(run, &distinct, 4, uint64_t{n} * 4);
  rep = dev.alloc(uint64_t{distinct} * 4, "representatives");
  dev.dispatch(dev.kernel(KernelId::dag_assign), groups, kLocal, {&keys, &order, &run, &id, &rep}, p);
  dev.barrier();
  if (class_keys) {
    std::vector<uint64_t> sorted(n);
    dev.download(keys, sorted.data(), uint64_t{n} * 8);
    class_keys->clear();
    class_keys->reserve(distinct);
    for (uint32_t i = 0; i < n; ++i)
      if (i == 0 || sorted[i] != sorted[i - 1]) class_keys->push_back(sorted[i]);
  }
  return distinct;
}

// Level 2: 4x4x4 bricks are exact 64-bit keys, nothing to verify. With symmetry equal bricks are grouped
// first (the plain reduction's work), then only those classes, few, are canonicalized (kernel brick_canon)
// and grouped again up to reflection; each node takes its class's id, T* and tag row (brick_orient).
void reduce_bricks(Device& dev, const SvoLevel& lv, const Reduced& below, Reduced& r, const Reduction& red,
                   std::vector<uint64_t>* class_keys) {
  const uint32_t n = lv.n;
  Buffer keys = dev.alloc(uint64_t{n} * 8, "bricks");
  Buffer order = dev.alloc(uint64_t{n} * 4, "brick order");
  const MvDagParams p{n, 0, 0, 0, 0, 0};
  dev.dispatch(dev.kernel(KernelId::brick_keys), dev.groups_for(n, kLocal), kLocal,
               {&lv.mask, &lv.first, &below.child_mask, &keys, &order}, p);
  dev.barrier();
  r.distinct = group_keys(dev, keys, order, n, r.id, r.rep, red.symmetric ? nullptr : class_keys);
  if (!red.symmetric) return;
  const uint32_t raw = r.distinct;
  Buffer raw_rep = std::move(r.rep);
  Buffer ckeys = dev.alloc(uint64_t{raw} * 8, "canonical bricks");
  Buffer corder = dev.alloc(uint64_t{raw} * 4, "canonical brick order");
  Buffer crow = dev.alloc(uint64_t{raw} * 4, "brick class orientations");
  dev.dispatch(dev.kernel(KernelId::brick_canon), dev.groups_for(raw, kLocal), kLocal,
               {&lv.mask, &red.mask_table, &lv.first, &below.child_mask, &raw_rep, &ckeys, &crow, &corder},
               MvDagParams{raw, 0, 0, 0, 0, 0});
  dev.barrier();
  Buffer cls = dev.alloc(uint64_t{raw} * 4, "brick classes");
  Buffer rep_class;
  r.distinct = group_keys(dev, ckeys, corder, raw, cls, rep_class, class_keys);
  r.rep = dev.alloc(uint64_t{r.distinct} * 4, "representative nodes");
  Buffer none;
  dev.dispatch(dev.kernel(KernelId::gather_slots), dev.groups_for(r.distinct, kLocal), kLocal,
               {&rep_class, &none, &raw_rep, &none, &r.rep, &none}, MvDagParams{r.distinct, 0, 0, 0, 0, 0});
  r.row = dev.alloc(uint64_t{n} * 4, "node orientations");
  dev.dispatch(dev.kernel(KernelId::brick_orient), dev.groups_for(n, kLocal), kLocal, {&r.id, &cls, &crow, &r.row}, p);
  dev.barrier();
}

// The canonical pass of a level above 2. CPU devices give each work-item a contiguous block of nodes, so a
// run of equal nodes (flat faces) is canonicalized once; GPUs keep one node per work-item (coalesced reads),
// and so do drivers that cap loop iterations (llvmpipe counts the inner loops' iterations over the whole
// block).
void dispatch_canon(Device& dev, const SvoLevel& lv, const Reduced& below, const Buffer& mtab, Buffer& row,
                    Buffer& hashes, Buffer& order, MvDagParams p) {
  uint32_t groups = dev.groups_for(lv.n, kLocal), local = kLocal;
  if (!dev.info().massively_parallel && dev.info().max_loop_iterations == 0) {
    BlockShape shape = block_shape(dev.info(), lv.n);
    p.block = shape.block_size;
    groups = shape.groups;
    local = shape.local_size;
  }
  dev.dispatch(dev.kernel(KernelId::ssvdag_canon), groups, local,
               {&lv.mask, &mtab, &lv.first, &below.id, &below.row, &row, &hashes, &order}, p);
}

}  // namespace

uint32_t test_hash_drop(uint32_t seed) {
  static const uint32_t drop = [] {
    const char* v = std::getenv("MEGAVOX_TEST_HASH_BITS");
    if (!v || !*v) return 0u;
    char* end = nullptr;
    const unsigned long bits = std::strtoul(v, &end, 10);
    if (*end || bits < 1 || bits > 64)
      throw Error("MEGAVOX_TEST_HASH_BITS: \"" + std::string(v) + "\" is not a bit count from 1 to 64");
    return static_cast<uint32_t>(64 - bits);
  }();
  return seed == 1 ? drop : 0u;
}

void report_test_collision(const char* where, uint32_t seed) {
  if (test_hash_drop(1)) std::fprintf(stderr, "megavox: test hash: seed %u collided %s; next seed\n", seed, where);
}

Reduction make_reduction(Device& dev, bool symmetric) {
  Reduction red;
  red.symmetric = symmetric;
  if (symmetric) red.mask_table = mask_table(dev);
  return red;
}

Reduced reduce_level(Device& dev, const SvoLevel& lv, const Reduced& below, bool leaf, const Reduction& red,
                     ClassKeys* keys) {
  const bool symmetric = red.symmetric;
  const uint32_t n = lv.n;
  Reduced r;
  if (leaf) {
    reduce_leaves(dev, lv, r, red);
    return r;
  }
  r.id = dev.alloc(uint64_t{n} * 4, "node ids");
  if (!below.child_mask.empty()) {
    reduce_bricks(dev, lv, below, r, red, keys ? &keys->keys : nullptr);
    return r;
  }
  Buffer hashes = dev.alloc(uint64_t{n} * 8, "node hashes");
  Buffer order = dev.alloc(uint64_t{n} * 4, "node order");
  Buffer collided = dev.alloc(4, "hash collision flag");
  const Buffer& mtab = red.mask_table;
  if (symmetric) r.row = dev.alloc(uint64_t{n} * 4, "node orientations");
  const uint32_t groups = dev.groups_for(n, kLocal);
  MvDagParams p{n, 0, 0, 0x6d766f78u, 0, 0};
  for (uint32_t seed = keys ? keys->seed : 1;; ++seed) {  // a new seed only after a 64-bit hash collision
    p.seed_lo = seed;
    p.hash_drop = test_hash_drop(seed);
    if (symmetric)  // T*, stabilizer and the canonical key's hash in one pass over the children
      dispatch_canon(dev, lv, below, mtab, r.row, hashes, order, p);
    else
      dev.dispatch(dev.kernel(KernelId::dag_hash), groups, kLocal, {&lv.mask, &lv.first, &below.id, &hashes, &order}, p);
    dev.barrier();
    r.distinct = group_keys(dev, hashes, order, n, r.id, r.rep, keys ? &keys->keys : nullptr);
    dev.fill(collided, 0, 4);
    dev.barrier();
    if (symmetric)
      dev.dispatch(dev.kernel(KernelId::ssvdag_verify), groups, kLocal,
                   {&lv.mask, &lv.first, &below.id, &below.row, &r.row, &r.id, &r.rep, &collided}, p);
    else
      dev.dispatch(dev.kernel(KernelId::dag_verify), groups, kLocal, {&lv.mask, &lv.first, &below.id, &r.id, &r.rep, &collided},
                   p);
    uint32_t bad = 0;
    dev.download(collided, &bad, 4);
    if (!bad) {
      if (keys) keys->seed = seed;
      break;
    }
    report_test_collision("on one rank", seed);
    if (seed >= 16) throw Error("DAG reduction: 16 hash seeds collided; this should not happen");
  }
  return r;
}

// No reduction (the plain octree): every node is its own class.
Reduced identity_level(Device& dev, const SvoLevel& lv) {
  Reduced r;
  r.distinct = lv.n;
  std::vector<uint32_t> iota(lv.n);
  for (uint32_t i = 0; i < lv.n; ++i) iota[i] = i;
  r.id = dev.alloc(uint64_t{lv.n} * 4, "octree node ids");
  dev.upload(r.id, iota.data(), uint64_t{lv.n} * 4);
  r.rep = dev.alloc(uint64_t{lv.n} * 4, "octree node ids");
  dev.upload(r.rep, iota.data(), uint64_t{lv.n} * 4);
  return r;
}

}  // namespace mv::detail
