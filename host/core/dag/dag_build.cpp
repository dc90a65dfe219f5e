// In-core DAG build on the device (kernels: kernels/common/dag.h): the octree levels built from sorted voxel
// keys, each level reduced (dag_reduce.cpp) and read back as a DAG level; and a DAG decoded back to voxels.
#include <algorithm>
#include <chrono>

#include "primitives/scan_plan.h"
#include "dag_build_steps.h"
#include "megavox/dag.h"
#include "megavox/error.h"
#include "megavox/primitives.h"
#include "timing.h"

namespace mv {

namespace detail {

namespace {

template <class T>
std::vector<T> fetch(Device& dev, const Buffer& b, size_t n) {
  std::vector<T> v(n);
  dev.download(b, v.data(), n * sizeof(T));
  return v;
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

}  // namespace

// Parents of the sorted unique keys in `below`.
SvoLevel build_parents(Device& dev, const Buffer& keys, uint32_t n) {
  SvoLevel up;
  Buffer pos = dev.alloc((uint64_t{n} + 1) * 4, "octree parent positions");
  MvDagParams p{n, 0, 0, 0, 0, 0};
  dev.dispatch(dev.kernel(KernelId::svo_flags), dev.groups_for(n, kLocal), kLocal, {&keys, &pos}, p);
  dev.barrier();
  ScanPlan scan = plan_scan(dev, n);
  record_scan(dev, scan, pos, pos);
  dev.download(pos, &up.n, 4, uint64_t{n} * 4);
  up.keys = dev.alloc(uint64_t{up.n} * 8, "octree node keys");
  up.mask = dev.alloc(uint64_t{up.n} * 4, "octree node masks");
  up.first = dev.alloc(uint64_t{up.n} * 4, "octree first children");
  dev.dispatch(dev.kernel(KernelId::svo_parents), dev.groups_for(n, kLocal), kLocal,
               {&keys, &pos, &up.keys, &up.mask, &up.first}, p);
  dev.barrier();
  return up;
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
  MvDagParams p{n, leaf ? 1u : 0u, symmetric ? 1u : 0u, 0, 0, 0};
  if (!below.child_mask.empty())  // reduced level 2: children (id, tag) from their masks
    dev.dispatch(dev.kernel(KernelId::brick_emit), dev.groups_for(n, kLocal), kLocal,
                 {&lv.mask, &lv.first, &below.child_mask, &red.mask_table, &below.class_rank, &r.row, &r.rep,
                  &masks, &entries},
                 p);
  else
    dev.dispatch(dev.kernel(KernelId::dag_emit), dev.groups_for(n, kLocal), kLocal,
                 {&lv.mask, &lv.first, &below.id, &below.row, &r.row, &r.rep, &masks, &entries}, p);
  out.mask = fetch<uint32_t>(dev, masks, n);
  if (leaf) return out;
  // Read back in chunks: the entries take 64 bytes a node, and the level's host copy needs 4 (8 with tags)
  // a child; holding all entries at once was the out-of-core merge's host peak.
  uint64_t children = 0;
  for (uint32_t m : out.mask) children += static_cast<uint64_t>(__builtin_popcount(m));
  out.first.resize(n);
  out.children.reserve(children);
  if (symmetric) out.tags.reserve(children);
  constexpr uint32_t kChunk = 1u << 18;
  std::vector<uint64_t> e(size_t{std::min(n, kChunk)} * 8);
  for (uint32_t c = 0; c < n; c += kChunk) {
    const uint32_t m = std::min(kChunk, n - c);
    dev.download(entries, e.data(), uint64_t{m} * 64, uint64_t{c} * 64);
    for (uint32_t i = c; i < c + m; ++i) {
      out.first[i] = static_cast<uint32_t>(out.children.size());
      for (uint32_t o = 0; o < 8; ++o) {
        if (!(out.mask[i] >> o & 1)) continue;
        out.children.push_back(mv_entry_id(e[8 * size_t{i - c} + o]));
        if (symmetric) out.tags.push_back(mv_entry_tag(e[8 * size_t{i - c} + o]));
      }
    }
  }
  return out;
}

// After the root level: wait, store the root unreflected, report the times.
void finish_build(Device& dev, Dag& dag, const Reduced& root, const Reduction& red, Clock::time_point t0,
                  Clock::time_point t1, DagBuildTimes* times) {
  uint32_t root_row = 0;
  if (dag.symmetric && !root.row.empty()) {
    dev.download(root.row, &root_row, 4);
  } else if (dag.symmetric) {  // a level-1 root: its mask's row in the mask table
    uint32_t m = 0;
    dev.download(root.child_mask, &m, 4);
    dev.download(red.mask_table, &root_row, 4, uint64_t{mv_mask_row_at(m)} * 4);
  }
  dev.finish();
  store_root_unreflected(dag, mv_row_field(root_row, 0));
  if (times) {
    times->svo_seconds = std::chrono::duration<double>(t1 - t0).count();
    times->reduce_seconds = seconds_since(t1);
  }
}

namespace {

// Levels 1 and 2 from the bricks (kernels brick_levels, brick_leaves): level 2 is the bricks, level 1 their
// non-zero bytes. A 2^1 grid has no level 2: its one brick's first byte is the root.
void bottom_levels(Device& dev, const Bricks& bricks, uint32_t levels, std::vector<SvoLevel>& svo) {
  const auto n = static_cast<uint32_t>(bricks.size());
  if (levels == 1) {
    const uint32_t root = static_cast<uint32_t>(bricks.masks[0] & 0xff);
    svo[1].n = 1;
    svo[1].mask = dev.alloc(4, "octree node masks");
    dev.upload(svo[1].mask, &root, 4);
    return;
  }
  SvoLevel& two = svo[2];
  two.n = n;
  two.keys = dev.alloc(uint64_t{n} * 8, "brick keys");
  dev.upload(two.keys, bricks.keys.data(), uint64_t{n} * 8);
  Buffer masks = dev.alloc(uint64_t{n} * 8, "brick masks");
  dev.upload(masks, bricks.masks.data(), uint64_t{n} * 8);
  two.mask = dev.alloc(uint64_t{n} * 4, "octree node masks");
  two.first = dev.alloc((uint64_t{n} + 1) * 4, "octree first children");
  const MvDagParams p{n, 0, 0, 0, 0, 0};
  dev.dispatch(dev.kernel(KernelId::brick_levels), dev.groups_for(n, kLocal), kLocal, {&masks, &two.mask, &two.first},
               p);
  dev.barrier();
  ScanPlan scan = plan_scan(dev, n);
  record_scan(dev, scan, two.first, two.first);
  dev.download(two.first, &svo[1].n, 4, uint64_t{n} * 4);
  svo[1].mask = dev.alloc(uint64_t{svo[1].n} * 4, "octree node masks");
  dev.dispatch(dev.kernel(KernelId::brick_leaves), dev.groups_for(n, kLocal), kLocal, {&masks, &two.first, &svo[1].mask},
               p);
  dev.barrier();
}

}  // namespace

// `shared`: a Reduction made by the caller for many builds (the out-of-core cubes); else one is made here.
Dag build_dag(Device& dev, const Bricks& bricks, uint32_t levels, bool symmetric, DagBuildTimes* times, bool reduce,
              const Reduction* shared) {
  if (levels < 1 || levels > 21) throw Error("DAG build: " + std::to_string(levels) + " levels is outside [1, 21]");
  if (bricks.size() > kMaxDeviceItems / 8)  // level 1 (up to 8 nodes a brick) is indexed by single device calls
    throw Error("DAG build: more than " + std::to_string(kMaxDeviceItems / 8) + " bricks in one build; build in cubes");
  const uint32_t brick_levels = levels < 2 ? 0 : levels - 2;
  if (!bricks.empty() && (bricks.keys.back() >> (3 * brick_levels) || (levels == 1 && bricks.masks[0] >> 8)))
    throw Error("DAG build: a voxel lies outside the 2^" + std::to_string(levels) + " grid");
  Dag dag;
  dag.levels = levels;
  dag.symmetric = symmetric;
  dag.reduced = reduce;
  dag.voxels = bricks.voxels();
  dag.svo_nodes.assign(levels + 1, 0);
  dag.level.resize(levels + 1);
  dag.svo_nodes[0] = dag.voxels;
  if (bricks.empty()) return dag;

  auto t0 = Clock::now();
  std::vector<SvoLevel> svo(levels + 1);
  bottom_levels(dev, bricks, levels, svo);
  for (uint32_t l = 1; l <= std::min(levels, 2u); ++l) dag.svo_nodes[l] = svo[l].n;
  for (uint32_t l = 3; l <= levels; ++l) {
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
    dev.finish();  // the scratch of the level below returns to the pool (retired buffers wait for a finish)
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

}  // namespace detail

using detail::build_dag;

namespace {
// Voxel keys as the key-based builds take them: sorted, unique, inside the grid.
Bricks checked_bricks(const std::vector<uint64_t>& voxels, uint32_t levels) {
  for (size_t i = 1; i < voxels.size(); ++i)
    if (voxels[i] <= voxels[i - 1]) throw Error("DAG build: the voxel keys are not sorted and unique");
  if (levels <= 21 && !voxels.empty() && voxels.back() >> (3 * levels))
    throw Error("DAG build: a voxel key lies outside the 2^" + std::to_string(levels) + " grid");
  return bricks_from_keys(voxels);
}
}  // namespace

Dag build_svdag(Device& dev, const Bricks& bricks, uint32_t levels, DagBuildTimes* times) {
  return build_dag(dev, bricks, levels, false, times);
}

Dag build_ssvdag(Device& dev, const Bricks& bricks, uint32_t levels, DagBuildTimes* times) {
  return build_dag(dev, bricks, levels, true, times);
}

Dag build_svo(Device& dev, const Bricks& bricks, uint32_t levels, DagBuildTimes* times) {
  return build_dag(dev, bricks, levels, false, times, false);
}

Dag build_svdag(Device& dev, const std::vector<uint64_t>& voxels, uint32_t levels, DagBuildTimes* times) {
  return build_svdag(dev, checked_bricks(voxels, levels), levels, times);
}

Dag build_ssvdag(Device& dev, const std::vector<uint64_t>& voxels, uint32_t levels, DagBuildTimes* times) {
  return build_ssvdag(dev, checked_bricks(voxels, levels), levels, times);
}

Dag build_svo(Device& dev, const std::vector<uint64_t>& voxels, uint32_t levels, DagBuildTimes* times) {
  return build_svo(dev, checked_bricks(voxels, levels), levels, times);
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
