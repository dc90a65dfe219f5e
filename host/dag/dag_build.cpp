// Host side of SVO level building and DAG reduction (kernels: kernels/common/dag.h).
#include "../../kernels/common/ssvdag.h"

#include <algorithm>
#include <chrono>

#include "../launch_shape.h"
#include "../scan_plan.h"
#include "megavox/dag.h"
#include "megavox/error.h"
#include "megavox/primitives.h"

namespace mv {

namespace {

using Clock = std::chrono::steady_clock;
constexpr uint32_t kLocal = 64;

// The octree level l as the device holds it while building: node keys, child masks, first children.
struct SvoLevel {
  uint32_t n = 0;
  Buffer keys, mask, first;
};

template <class T>
std::vector<T> fetch(Device& dev, const Buffer& b, size_t n) {
  std::vector<T> v(n);
  dev.download(b, v.data(), n * sizeof(T));
  return v;
}

// Parents of the sorted unique keys in `below`.
SvoLevel build_parents(Device& dev, const Buffer& keys, uint32_t n) {
  SvoLevel up;
  Buffer pos = dev.alloc((uint64_t{n} + 1) * 4, "octree parent positions");
  MvDagParams p{n, 0, 0, 0, 0};
  dev.dispatch(dev.kernel("svo_flags"), dev.groups_for(n, kLocal), kLocal, {&keys, &pos}, p);
  dev.barrier();
  ScanPlan scan = plan_scan(dev, n);
  record_scan(dev, scan, pos, pos);
  dev.download(pos, &up.n, 4, uint64_t{n} * 4);
  up.keys = dev.alloc(uint64_t{up.n} * 8, "octree node keys");
  up.mask = dev.alloc(uint64_t{up.n} * 4, "octree node masks");
  up.first = dev.alloc(uint64_t{up.n} * 4, "octree first children");
  dev.dispatch(dev.kernel("svo_parents"), dev.groups_for(n, kLocal), kLocal,
               {&keys, &pos, &up.keys, &up.mask, &up.first}, p);
  dev.barrier();
  return up;
}

// Distinct subtrees of one level: id per node, the representative node of each id and, for the SSVDAG,
// each node's orientation (row): its tag as its parent will point to it as a tag row (field k = that tag
// seen through reflection k, normalized by the node's stabilizer) and its T* (kernels/common/ssvdag.h).
struct Reduced {
  uint32_t distinct = 0;
  Buffer id, rep, row;
  // Reduced level 1 keeps no ids per node: level 2 reads its children's masks (child_mask: one per node, or
  // per merge slot), and its emit ranks them (class_rank: the rank of each 8-bit class, 257 entries).
  Buffer class_mask;  // each class's stored mask (canonical with symmetry)
  Buffer class_rank, child_mask;
};

// Canonical form, T*, stabilizer and tag row of every 8-bit mask (kernel leaf_table).
Buffer mask_table(Device& dev) {
  Buffer table = dev.alloc(768 * 4, "mask table");
  dev.dispatch(dev.kernel("leaf_table"), dev.groups_for(256, kLocal), kLocal, {&table}, MvDagParams{256, 0, 0, 0, 0});
  dev.barrier();
  return table;
}

// How a build reduces its levels: plainly, or up to reflections with the mask table made once per build.
struct Reduction {
  bool symmetric = false;
  Buffer mask_table;  // symmetric only
};

Reduction make_reduction(Device& dev, bool symmetric) {
  Reduction red;
  red.symmetric = symmetric;
  if (symmetric) red.mask_table = mask_table(dev);
  return red;
}

// Level 1: classes are (canonical) masks, ranked without hashing (kernels: leaf_table, leaf_present,
// leaf_classes); nothing is written per node.
void reduce_leaves(Device& dev, const SvoLevel& lv, Reduced& r, const Reduction& red) {
  const bool symmetric = red.symmetric;
  const Buffer& table = red.mask_table;
  MvDagParams p{lv.n, symmetric ? 2u : 1u, 0, 0, 0};
  Buffer& present = r.class_rank;
  present = dev.alloc(257 * 4, "leaf classes");
  dev.fill(present, 0, 257 * 4);
  dev.barrier();
  const uint32_t groups = dev.groups_for(lv.n, kLocal);
  dev.dispatch(dev.kernel("leaf_present"), groups, kLocal, {&lv.mask, &table, &present}, p);
  dev.barrier();
  exclusive_scan(dev, present, present, 256);
  dev.download(present, &r.distinct, 4, 256 * 4);
  r.class_mask = dev.alloc(uint64_t{r.distinct} * 4, "leaf class masks");
  dev.dispatch(dev.kernel("leaf_classes"), dev.groups_for(256, kLocal), kLocal, {&present, &r.class_mask}, p);
  dev.barrier();
}

// Equal keys grouped: sort (keys, order), mark runs, rank them: id per item, the first item of each run as
// its representative; returns the number of runs.
uint32_t group_keys(Device& dev, Buffer& keys, Buffer& order, uint32_t n, Buffer& id, Buffer& rep) {
  Buffer run = dev.alloc((uint64_t{n} + 1) * 4, "key runs");
  const uint32_t groups = dev.groups_for(n, kLocal);
  const MvDagParams p{n, 0, 0, 0, 0};
  radix_sort(dev, keys, &order, n, KeyBits::k64);
  dev.dispatch(dev.kernel("dag_runs"), groups, kLocal, {&keys, &run}, p);
  dev.barrier();
  ScanPlan scan = plan_scan(dev, n);
  record_scan(dev, scan, run, run);
  uint32_t distinct = 0;
  dev.download(run, &distinct, 4, uint64_t{n} * 4);
  rep = dev.alloc(uint64_t{distinct} * 4, "representatives");
  dev.dispatch(dev.kernel("dag_assign"), groups, kLocal, {&keys, &order, &run, &id, &rep}, p);
  dev.barrier();
  return distinct;
}

// Level 2: 4x4x4 bricks are exact 64-bit keys, nothing to verify. With symmetry equal bricks are grouped
// first (the plain reduction's work), then only those classes, few, are canonicalized (kernel brick_canon)
// and grouped again up to reflection; each node takes its class's id, T* and tag row (brick_orient).
void reduce_bricks(Device& dev, const SvoLevel& lv, const Reduced& below, Reduced& r, const Reduction& red) {
  const uint32_t n = lv.n;
  Buffer keys = dev.alloc(uint64_t{n} * 8, "bricks");
  Buffer order = dev.alloc(uint64_t{n} * 4, "brick order");
  const MvDagParams p{n, 0, 0, 0, 0};
  dev.dispatch(dev.kernel("brick_keys"), dev.groups_for(n, kLocal), kLocal,
               {&lv.mask, &lv.first, &below.child_mask, &keys, &order}, p);
  dev.barrier();
  r.distinct = group_keys(dev, keys, order, n, r.id, r.rep);
  if (!red.symmetric) return;
  const uint32_t raw = r.distinct;
  Buffer raw_rep = std::move(r.rep);
  Buffer ckeys = dev.alloc(uint64_t{raw} * 8, "canonical bricks");
  Buffer corder = dev.alloc(uint64_t{raw} * 4, "canonical brick order");
  Buffer crow = dev.alloc(uint64_t{raw} * 4, "brick class orientations");
  dev.dispatch(dev.kernel("brick_canon"), dev.groups_for(raw, kLocal), kLocal,
               {&lv.mask, &red.mask_table, &lv.first, &below.child_mask, &raw_rep, &ckeys, &crow, &corder},
               MvDagParams{raw, 0, 0, 0, 0});
  dev.barrier();
  Buffer cls = dev.alloc(uint64_t{raw} * 4, "brick classes");
  Buffer rep_class;
  r.distinct = group_keys(dev, ckeys, corder, raw, cls, rep_class);
  r.rep = dev.alloc(uint64_t{r.distinct} * 4, "representative nodes");
  Buffer none;
  dev.dispatch(dev.kernel("gather_slots"), dev.groups_for(r.distinct, kLocal), kLocal,
               {&rep_class, &none, &raw_rep, &none, &r.rep, &none}, MvDagParams{r.distinct, 0, 0, 0, 0});
  r.row = dev.alloc(uint64_t{n} * 4, "node orientations");
  dev.dispatch(dev.kernel("brick_orient"), dev.groups_for(n, kLocal), kLocal, {&r.id, &cls, &crow, &r.row}, p);
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
  dev.dispatch(dev.kernel("ssvdag_canon"), groups, local,
               {&lv.mask, &mtab, &lv.first, &below.id, &below.row, &row, &hashes, &order}, p);
}

Reduced reduce_level(Device& dev, const SvoLevel& lv, const Reduced& below, bool leaf, const Reduction& red) {
  const bool symmetric = red.symmetric;
  const uint32_t n = lv.n;
  Reduced r;
  if (leaf) {
    reduce_leaves(dev, lv, r, red);
    return r;
  }
  r.id = dev.alloc(uint64_t{n} * 4, "node ids");
  if (!below.child_mask.empty()) {
    reduce_bricks(dev, lv, below, r, red);
    return r;
  }
  Buffer hashes = dev.alloc(uint64_t{n} * 8, "node hashes");
  Buffer order = dev.alloc(uint64_t{n} * 4, "node order");
  Buffer collided = dev.alloc(4, "hash collision flag");
  const Buffer& mtab = red.mask_table;
  if (symmetric) r.row = dev.alloc(uint64_t{n} * 4, "node orientations");
  const uint32_t groups = dev.groups_for(n, kLocal);
  MvDagParams p{n, 0, 0, 0x6d766f78u, 0};
  for (uint32_t seed = 1;; ++seed) {  // a new seed only after a 64-bit hash collision
    p.seed_lo = seed;
    if (symmetric)  // T*, stabilizer and the canonical key's hash in one pass over the children
      dispatch_canon(dev, lv, below, mtab, r.row, hashes, order, p);
    else
      dev.dispatch(dev.kernel("dag_hash"), groups, kLocal, {&lv.mask, &lv.first, &below.id, &hashes, &order}, p);
    dev.barrier();
    r.distinct = group_keys(dev, hashes, order, n, r.id, r.rep);
    dev.fill(collided, 0, 4);
    dev.barrier();
    if (symmetric)
      dev.dispatch(dev.kernel("ssvdag_verify"), groups, kLocal,
                   {&lv.mask, &lv.first, &below.id, &below.row, &r.row, &r.id, &r.rep, &collided}, p);
    else
      dev.dispatch(dev.kernel("dag_verify"), groups, kLocal, {&lv.mask, &lv.first, &below.id, &r.id, &r.rep, &collided},
                   p);
    uint32_t bad = 0;
    dev.download(collided, &bad, 4);
    if (!bad) break;
    if (seed == 16) throw Error("DAG reduction: 16 hash seeds collided; this should not happen");
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

// The DAG level in id order: each representative in its stored orientation (reflected by its T* for the
// SSVDAG) with its children's (id, tag) in octant order; gathered on the device (kernel dag_emit) and read
// back sequentially (gathering on the host was the slowest part of a reduction: random reads).
DagLevel assemble(Device& dev, const SvoLevel& lv, const Reduced& r, const Reduced& below, bool leaf,
                  const Reduction& red) {
  DagLevel out;
  const bool symmetric = red.symmetric;
  const uint32_t n = r.distinct;
  if (leaf && !r.class_mask.empty()) {  // reduced level 1: the class masks are the level
    out.mask = fetch<uint32_t>(dev, r.class_mask, n);
    return out;
  }
  Buffer masks = dev.alloc(uint64_t{n} * 4, "DAG level masks");
  Buffer entries = leaf ? Buffer() : dev.alloc(uint64_t{n} * 64, "DAG level entries");
  MvDagParams p{n, leaf ? 1u : 0u, symmetric ? 1u : 0u, 0, 0};
  if (!below.child_mask.empty())  // reduced level 2: children (id, tag) from their masks
    dev.dispatch(dev.kernel("brick_emit"), dev.groups_for(n, kLocal), kLocal,
                 {&lv.mask, &lv.first, &below.child_mask, &red.mask_table, &below.class_rank, &r.row, &r.rep,
                  &masks, &entries},
                 p);
  else
    dev.dispatch(dev.kernel("dag_emit"), dev.groups_for(n, kLocal), kLocal,
                 {&lv.mask, &lv.first, &below.id, &below.row, &r.row, &r.rep, &masks, &entries}, p);
  out.mask = fetch<uint32_t>(dev, masks, n);
  if (leaf) return out;
  std::vector<uint64_t> e = fetch<uint64_t>(dev, entries, size_t{n} * 8);
  out.first.resize(n);
  for (uint32_t i = 0; i < n; ++i) {
    out.first[i] = static_cast<uint32_t>(out.children.size());
    for (uint32_t o = 0; o < 8; ++o) {
      if (!(out.mask[i] >> o & 1)) continue;
      out.children.push_back(static_cast<uint32_t>(e[8 * size_t{i} + o] >> 3));
      if (symmetric) out.tags.push_back(static_cast<uint32_t>(e[8 * size_t{i} + o] & 7));
    }
  }
  return out;
}

// The root was stored canonically reflected by its tag; store it in the model's own orientation instead
// (nothing else points to it), as the SymVox formats do: octant c moves to c ^ t, child tags pick up t.
void store_root_unreflected(Dag& dag, uint32_t t) {
  if (t == 0) return;
  DagLevel& top = dag.level[dag.levels];
  const uint32_t m = top.mask[0];
  top.mask[0] = mv_reflect_mask(m, t);
  if (dag.levels == 1) return;
  uint32_t ids[8] = {}, tags[8] = {};
  for (uint32_t c = 0, k = 0; c < 8; ++c)
    if (m >> c & 1) {
      ids[c ^ t] = top.children[k];
      tags[c ^ t] = top.tags[k++] ^ t;
    }
  top.children.clear();
  top.tags.clear();
  for (uint32_t c = 0; c < 8; ++c)
    if (top.mask[0] >> c & 1) {
      top.children.push_back(ids[c]);
      top.tags.push_back(tags[c]);
    }
}

// After the root level: wait, store the root unreflected, report the times.
void finish_build(Device& dev, Dag& dag, const Reduced& root, const Reduction& red, Clock::time_point t0,
                  Clock::time_point t1, DagBuildTimes* times) {
  uint32_t root_row = 0;  // field 0: the root's tag
  if (dag.symmetric && !root.row.empty()) {
    dev.download(root.row, &root_row, 4);
  } else if (dag.symmetric) {  // a level-1 root: its mask's row in the mask table
    uint32_t m = 0;
    dev.download(root.child_mask, &m, 4);
    dev.download(red.mask_table, &root_row, 4, (2 * uint64_t{m} + 1) * 4);
  }
  dev.finish();
  store_root_unreflected(dag, root_row & 7);
  if (times) {
    times->svo_seconds = std::chrono::duration<double>(t1 - t0).count();
    times->reduce_seconds = std::chrono::duration<double>(Clock::now() - t1).count();
  }
}

// `shared`: a Reduction made by the caller for many builds (the out-of-core cubes); else one is made here.
Dag build_dag(Device& dev, const std::vector<uint64_t>& voxels, uint32_t levels, bool symmetric,
              DagBuildTimes* times, bool reduce = true, const Reduction* shared = nullptr) {
  if (levels < 1 || levels > 21) throw Error("DAG build: " + std::to_string(levels) + " levels is outside [1, 21]");
  if (voxels.size() > UINT32_MAX) throw Error("DAG build: more than 2^32-1 voxels in one build");
  if (!voxels.empty() && voxels.back() >> (3 * levels))
    throw Error("DAG build: a voxel key lies outside the 2^" + std::to_string(levels) + " grid");
  Dag dag;
  dag.levels = levels;
  dag.symmetric = symmetric;
  dag.reduced = reduce;
  dag.voxels = voxels.size();
  dag.svo_nodes.assign(levels + 1, 0);
  dag.level.resize(levels + 1);
  dag.svo_nodes[0] = voxels.size();
  if (voxels.empty()) return dag;

  auto t0 = Clock::now();
  std::vector<SvoLevel> svo(levels + 1);
  svo[0].n = static_cast<uint32_t>(voxels.size());
  svo[0].keys = dev.alloc(voxels.size() * 8, "voxel keys");
  dev.upload(svo[0].keys, voxels.data(), voxels.size() * 8);
  for (uint32_t l = 1; l <= levels; ++l) {
    svo[l] = build_parents(dev, svo[l - 1].keys, svo[l - 1].n);
    svo[l - 1].keys = Buffer();  // keys are only needed to find parents
    dag.svo_nodes[l] = svo[l].n;
  }
  dev.finish();
  auto t1 = Clock::now();

  Reduction own;
  if (!shared) own = make_reduction(dev, reduce && symmetric);
  const Reduction& red = shared ? *shared : own;
  Reduced below;
  for (uint32_t l = 1; l <= levels; ++l) {
    const bool leaf = l == 1;
    Reduced r = reduce ? reduce_level(dev, svo[l], below, leaf, red) : identity_level(dev, svo[l]);
    dag.level[l] = assemble(dev, svo[l], r, below, leaf, red);
    if (leaf && reduce) r.child_mask = std::move(svo[1].mask);
    below = std::move(r);
    svo[l - 1] = SvoLevel();
  }
  finish_build(dev, dag, below, red, t0, t1, times);
  return dag;
}

// The union of the cubes' partial DAGs at one level: nodes in their stored orientation, and one slot per
// child pointer (the union node it points to, the pointer's tag).
struct UnionLevel {
  std::vector<uint32_t> mask, first, slot_node, slot_tag;
};

// Merged classes of one union level (or of the cube roots): per slot, the class id and tag it points to.
// Above a reduced level 1, each slot's 2x2x2 mask as it lies instead (its node's stored mask, from
// below_masks, reflected by the slot's tag), as level 2 reads them.
Reduced gather(Device& dev, const UnionLevel& u, Reduced& merged, bool symmetric,
               const std::vector<uint32_t>& below_masks) {
  const auto n = static_cast<uint32_t>(u.slot_node.size());
  Reduced slots;
  slots.distinct = merged.distinct;
  slots.class_mask = std::move(merged.class_mask);
  if (n == 0) return slots;
  if (!merged.class_rank.empty()) {
    std::vector<uint32_t> masks(n);
    for (uint32_t i = 0; i < n; ++i)
      masks[i] = mv_reflect_mask(below_masks[u.slot_node[i]], symmetric ? u.slot_tag[i] : 0);
    slots.child_mask = dev.alloc(uint64_t{n} * 4, "merge slot masks");
    dev.upload(slots.child_mask, masks.data(), uint64_t{n} * 4);
    slots.class_rank = std::move(merged.class_rank);
    return slots;
  }
  Buffer node = dev.alloc(uint64_t{n} * 4, "merge slots");
  dev.upload(node, u.slot_node.data(), uint64_t{n} * 4);
  Buffer tag;
  if (symmetric) {
    tag = dev.alloc(uint64_t{n} * 4, "merge slot tags");
    dev.upload(tag, u.slot_tag.data(), uint64_t{n} * 4);
    slots.row = dev.alloc(uint64_t{n} * 4, "merged slot tag rows");
  }
  slots.id = dev.alloc(uint64_t{n} * 4, "merged slot ids");
  MvDagParams p{n, symmetric ? 1u : 0u, 0, 0, 0};
  dev.dispatch(dev.kernel("gather_slots"), dev.groups_for(n, kLocal), kLocal,
               {&node, &tag, &merged.id, &merged.row, &slots.id, &slots.row}, p);
  dev.barrier();
  return slots;
}

SvoLevel upload_level(Device& dev, const UnionLevel& u) {
  SvoLevel lv;
  lv.n = static_cast<uint32_t>(u.mask.size());
  lv.mask = dev.alloc(uint64_t{lv.n} * 4, "merge masks");
  dev.upload(lv.mask, u.mask.data(), uint64_t{lv.n} * 4);
  if (!u.first.empty()) {
    lv.first = dev.alloc(uint64_t{lv.n} * 4, "merge first slots");
    dev.upload(lv.first, u.first.data(), uint64_t{lv.n} * 4);
  }
  return lv;
}

}  // namespace

Dag build_svdag(Device& dev, const std::vector<uint64_t>& voxels, uint32_t levels, DagBuildTimes* times) {
  return build_dag(dev, voxels, levels, false, times);
}

Dag build_ssvdag(Device& dev, const std::vector<uint64_t>& voxels, uint32_t levels, DagBuildTimes* times) {
  return build_dag(dev, voxels, levels, true, times);
}

Dag build_svo(Device& dev, const std::vector<uint64_t>& voxels, uint32_t levels, DagBuildTimes* times) {
  return build_dag(dev, voxels, levels, false, times, false);
}

namespace {

// Out of core, reduced (plain or symmetric) or not (the octree: every level is kept whole, in key order).
Dag build_by_cubes(Device& dev, uint32_t levels, uint32_t cube_levels, bool symmetric, bool reduce,
                   const CubeVoxels& voxels_of, DagBuildTimes* times) {
  if (cube_levels < 1 || cube_levels >= levels)
    throw Error("out-of-core build: cubes of 2^" + std::to_string(cube_levels) + " voxels must be smaller than the 2^" +
                std::to_string(levels) + " grid");
  auto t0 = Clock::now();
  Dag dag;
  dag.levels = levels;
  dag.symmetric = symmetric;
  dag.reduced = reduce;
  dag.svo_nodes.assign(levels + 1, 0);
  dag.level.resize(levels + 1);
  const Reduction red = make_reduction(dev, reduce && symmetric);  // shared by the cubes and the merge
  // 1. Each cube on its own, in Morton order; its partial DAG joins the union, level by level.
  std::vector<UnionLevel> u(cube_levels + 1);
  std::vector<uint64_t> root_keys;   // Morton key of each non-empty cube at level cube_levels
  std::vector<uint32_t> root_node;   // its root in the union's top level
  const uint32_t side = 1u << cube_levels;
  const uint64_t cubes = uint64_t{1} << (3 * (levels - cube_levels));
  const uint64_t local_mask = (uint64_t{1} << (3 * cube_levels)) - 1;
  for (uint64_t c = 0; c < cubes; ++c) {
    uint32_t x = 0, y = 0, z = 0;
    for (uint32_t b = 0; b < levels - cube_levels; ++b) {
      x |= uint32_t(c >> (3 * b) & 1) << b;
      y |= uint32_t(c >> (3 * b + 1) & 1) << b;
      z |= uint32_t(c >> (3 * b + 2) & 1) << b;
    }
    Dag part;
    try {
      std::vector<uint64_t> keys = voxels_of(x * side, y * side, z * side, side);
      if (keys.empty()) continue;
      for (uint64_t& k : keys) {
        if ((k >> (3 * cube_levels)) != c) throw Error("out-of-core build: a voxel lies outside its cube");
        k &= local_mask;
      }
      part = build_dag(dev, keys, cube_levels, symmetric, nullptr, reduce, &red);
    } catch (const DeviceMemoryError& e) {
      throw CubeMemoryError(std::string(e.what()) + " (in a cube of " + std::to_string(side) + "^3)");
    }
    dag.voxels += part.voxels;
    for (uint32_t l = 0; l <= cube_levels; ++l) dag.svo_nodes[l] += part.svo_nodes[l];
    for (uint32_t l = 1; l <= cube_levels; ++l) {
      const DagLevel& p = part.level[l];
      UnionLevel& ul = u[l];
      const auto below_base = l > 1 ? static_cast<uint32_t>(u[l - 1].mask.size() - part.level[l - 1].mask.size()) : 0;
      for (size_t i = 0; i < p.mask.size(); ++i) {
        ul.mask.push_back(p.mask[i]);
        if (l == 1) continue;
        ul.first.push_back(static_cast<uint32_t>(ul.slot_node.size()));
        for (uint32_t k = 0; k < static_cast<uint32_t>(__builtin_popcount(p.mask[i])); ++k) {
          ul.slot_node.push_back(below_base + p.children[p.first[i] + k]);
          ul.slot_tag.push_back(p.tags.empty() ? 0 : p.tags[p.first[i] + k]);
        }
      }
    }
    root_keys.push_back(c);
    root_node.push_back(static_cast<uint32_t>(u[cube_levels].mask.size() - 1));
  }
  if (root_keys.empty()) return dag;
  auto t1 = Clock::now();

  // 2. Reduce the union again, bottom-up, exactly as an in-core build reduces its octree levels: the same
  // hashes of the same (mask, child class, tag) give the same classes, ids and stored orientations.
  Reduced below;
  for (uint32_t l = 1; l <= cube_levels; ++l) {
    SvoLevel lv = upload_level(dev, u[l]);
    Reduced slots = l == 1 ? Reduced() : gather(dev, u[l], below, symmetric, u[l - 1].mask);
    Reduced r = reduce ? reduce_level(dev, lv, slots, l == 1, red) : identity_level(dev, lv);
    dag.level[l] = assemble(dev, lv, r, slots, l == 1, red);
    below = std::move(r);
    u[l - 1] = UnionLevel();
  }
  // 3. Above the cubes: an octree over the cube roots, whose slots point at the roots' classes.
  SvoLevel roots;
  roots.n = static_cast<uint32_t>(root_keys.size());
  roots.keys = dev.alloc(uint64_t{roots.n} * 8, "cube keys");
  dev.upload(roots.keys, root_keys.data(), uint64_t{roots.n} * 8);
  UnionLevel root_slots;
  root_slots.slot_node = root_node;
  root_slots.slot_tag.assign(root_node.size(), 0);
  Reduced slots = gather(dev, root_slots, below, symmetric, u[cube_levels].mask);
  for (uint32_t l = cube_levels + 1; l <= levels; ++l) {
    SvoLevel lv = build_parents(dev, roots.keys, roots.n);
    dag.svo_nodes[l] = lv.n;
    Reduced r = reduce ? reduce_level(dev, lv, slots, false, red) : identity_level(dev, lv);
    dag.level[l] = assemble(dev, lv, r, slots, false, red);
    roots = std::move(lv);
    slots = std::move(r);
  }
  finish_build(dev, dag, slots, red, t0, t1, times);
  return dag;
}

}  // namespace

Dag build_dag_by_cubes(Device& dev, uint32_t levels, uint32_t cube_levels, bool symmetric, const CubeVoxels& voxels_of,
                       DagBuildTimes* times) {
  return build_by_cubes(dev, levels, cube_levels, symmetric, true, voxels_of, times);
}

Dag build_svo_by_cubes(Device& dev, uint32_t levels, uint32_t cube_levels, const CubeVoxels& voxels_of,
                       DagBuildTimes* times) {
  return build_by_cubes(dev, levels, cube_levels, false, false, voxels_of, times);
}

std::vector<uint64_t> decode_voxels(const Dag& dag) {
  std::vector<uint64_t> out;
  if (dag.levels == 0 || dag.level[dag.levels].mask.empty()) return out;
  // Depth-first from the root; the key prefix grows by one octant per level. `reflect` is the reflection
  // accumulated along the path: the subtree is reflect(stored node), so stored octant c lands at c ^ reflect.
  struct Item {
    uint32_t level, node, reflect;
    uint64_t prefix;
  };
  std::vector<Item> stack{{dag.levels, 0, 0, 0}};
  while (!stack.empty()) {
    Item it = stack.back();
    stack.pop_back();
    const DagLevel& lv = dag.level[it.level];
    uint32_t m = lv.mask[it.node];
    for (uint32_t c = 0, k = 0; c < 8; ++c) {
      if (!(m >> c & 1)) continue;
      uint64_t key = it.prefix << 3 | uint64_t(c ^ it.reflect);
      if (it.level == 1) {
        out.push_back(key);
      } else {
        uint32_t j = lv.first[it.node] + k;
        uint32_t tag = lv.tags.empty() ? 0 : lv.tags[j];
        stack.push_back({it.level - 1, lv.children[j], it.reflect ^ tag, key});
      }
      ++k;
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace mv
