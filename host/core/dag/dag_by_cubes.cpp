// Out-of-core DAG build: the grid cut into cubes, each built on its own (in core), their partial DAGs joined
// level by level and reduced again as one, then an octree over the cube roots up to the full grid.
#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dag_build_steps.h"
#include "merge_over_ranks.h"
#include "union_level.h"
#include "megavox/dag.h"
#include "megavox/error.h"

namespace mv {

namespace {

using namespace detail;


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
  MvDagParams p{n, symmetric ? 1u : 0u, 0, 0, 0, 0};
  dev.dispatch(dev.kernel(KernelId::gather_slots), dev.groups_for(n, kLocal), kLocal,
               {&node, &tag, &merged.id, &merged.row, &slots.id, &slots.row}, p);
  dev.barrier();
  return slots;
}

SvoLevel upload_level(Device& dev, const UnionLevel& u) {
  SvoLevel lv;
  lv.n = static_cast<uint32_t>(u.mask.size());
  if (lv.n == 0) return lv;  // a rank without cubes, merging over ranks
  lv.mask = dev.alloc(uint64_t{lv.n} * 4, "merge masks");
  dev.upload(lv.mask, u.mask.data(), uint64_t{lv.n} * 4);
  if (!u.first.empty()) {
    lv.first = dev.alloc(uint64_t{lv.n} * 4, "merge first slots");
    dev.upload(lv.first, u.first.data(), uint64_t{lv.n} * 4);
  }
  return lv;
}

// Out of core, reduced (plain or symmetric) or not (the octree: every level is kept whole, in key order).
Dag build_by_cubes(Device& dev, uint32_t levels, uint32_t cube_levels, bool symmetric, bool reduce,
                   const CubeVoxels& voxels_of, DagBuildTimes* times, const CubeExchange* exchange) {
  if (cube_levels < 2 || cube_levels >= levels)
    throw Error("out-of-core build: cubes of 2^" + std::to_string(cube_levels) +
                " voxels must hold a 4^3 brick and be smaller than the 2^" + std::to_string(levels) + " grid");
  auto t0 = Clock::now();
  Dag dag;
  dag.levels = levels;
  dag.symmetric = symmetric;
  dag.reduced = reduce;
  dag.svo_nodes.assign(levels + 1, 0);
  dag.level.resize(levels + 1);
  const Reduction red = make_reduction(dev, reduce && symmetric);  // shared by the cubes and the merge
  // 1. Each cube on its own, in Morton order; its partial DAG joins the union, level by level.
  std::vector<UnionLevel> u(cube_levels + 1, UnionLevel(reduce));
  std::vector<uint64_t> root_keys;   // Morton key of each non-empty cube at level cube_levels
  std::vector<uint32_t> root_node;   // its root in the union's top level
  const uint32_t side = 1u << cube_levels;
  const uint64_t cubes = uint64_t{1} << (3 * (levels - cube_levels));
  const uint64_t local_mask = (uint64_t{1} << (3 * (cube_levels - 2))) - 1;  // brick keys in the cube
  // Over ranks, a reduced build merges each rank's own parts and reduces the levels together.
  const RankCollectives* over = reduce && exchange ? exchange->collectives : nullptr;
  const bool payloads = exchange && exchange->take_payload;
  // A cube of this process: kept by an earlier run of the same build, else made now (nullopt: empty).
  auto own_part = [&](uint64_t c, uint32_t x, uint32_t y, uint32_t z) -> std::optional<Dag> {
    if (exchange && exchange->load) {
      std::vector<uint8_t> payload;
      if (std::optional<Dag> kept = exchange->load(c, payload)) {
        if (exchange->put_payload) exchange->put_payload(payload);
        return kept;
      }
    }
    Dag part;
    try {
      Bricks bricks = voxels_of(x * side, y * side, z * side, side);
      if (bricks.empty()) return std::nullopt;
      for (uint64_t& k : bricks.keys) {
        if ((k >> (3 * (cube_levels - 2))) != c) throw Error("out-of-core build: a voxel lies outside its cube");
        k &= local_mask;
      }
      part = build_dag(dev, bricks, cube_levels, symmetric, nullptr, reduce, &red);
    } catch (const DeviceMemoryError& e) {
      throw CubeMemoryError(std::string(e.what()) + " (in a cube of " + std::to_string(side) + "^3)");
    }
    if (exchange && exchange->keep) exchange->keep(c, part, exchange->peek_payload ? exchange->peek_payload() : std::vector<uint8_t>());
    return part;
  };
  for (uint64_t c = 0; c < cubes; ++c) {
    uint32_t x = 0, y = 0, z = 0;
    for (uint32_t b = 0; b < levels - cube_levels; ++b) {
      x |= uint32_t(c >> (3 * b) & 1) << b;
      y |= uint32_t(c >> (3 * b + 1) & 1) << b;
      z |= uint32_t(c >> (3 * b + 2) & 1) << b;
    }
    Dag part;
    if (exchange && exchange->mine && !exchange->mine(c)) {  // another process's cube
      if (!exchange->merges) continue;
      if (over) {  // its part stays there; its payload comes here
        if (payloads) {
          std::vector<uint8_t> payload;
          exchange->receive_payload(c, payload);
          exchange->put_payload(payload);
        }
        continue;
      }
      std::vector<uint8_t> payload;
      std::optional<Dag> made = exchange->receive(c, payload);
      if (!made) continue;
      if (exchange->put_payload) exchange->put_payload(payload);
      part = std::move(*made);
    } else {
      std::optional<Dag> own = own_part(c, x, y, z);
      if (!own) {
        if (exchange && !exchange->merges && (!over || payloads))
          over ? exchange->send_payload(c, {}) : exchange->send(c, nullptr, {});
        continue;
      }
      part = std::move(*own);
    }
    if (over && !exchange->merges && payloads) exchange->send_payload(c, exchange->take_payload());
    if (exchange && !exchange->merges && !over) {
      dag.voxels += part.voxels;  // what this process made, for its report
      exchange->send(c, &part, exchange->take_payload ? exchange->take_payload() : std::vector<uint8_t>());
      continue;
    }
    dag.voxels += part.voxels;
    for (uint32_t l = 0; l <= cube_levels; ++l) dag.svo_nodes[l] += part.svo_nodes[l];
    // Append the partial DAG to the union, level by level; `remap` takes its nodes one level down to theirs
    // in the union (deduplicated when reducing).
    std::vector<uint32_t> remap, up, nodes, tags;
    for (uint32_t l = 1; l <= cube_levels; ++l) {
      const DagLevel& p = part.level[l];
      up.resize(p.mask.size());
      for (size_t i = 0; i < p.mask.size(); ++i) {
        if (l == 1) {
          up[i] = u[l].add(p.mask[i], nullptr, nullptr);
          continue;
        }
        const auto k = static_cast<uint32_t>(__builtin_popcount(p.mask[i]));
        nodes.resize(k);
        tags.assign(k, 0);
        for (uint32_t j = 0; j < k; ++j) {
          nodes[j] = remap[p.children[p.first[i] + j]];
          if (!p.tags.empty()) tags[j] = p.tags[p.first[i] + j];
        }
        up[i] = u[l].add(p.mask[i], nodes.data(), tags.data());
      }
      remap.swap(up);
    }
    root_keys.push_back(c);
    root_node.push_back(remap[0]);  // the cube's root
  }
  std::optional<RankMerge> merge;
  if (over) {
    merge.emplace(RankMerge{*over});
    // Every rank's counts: the merging one reports the whole build's, the others what they made.
    std::vector<uint64_t> counts{root_keys.size(), dag.voxels};
    counts.insert(counts.end(), dag.svo_nodes.begin(), dag.svo_nodes.begin() + cube_levels + 1);
    const std::vector<uint64_t> sums = sum_over_ranks(*over, counts);
    if (sums[0] == 0) return dag;  // no cube of any rank has a voxel
    if (exchange->merges) {
      dag.voxels = sums[1];
      std::copy(sums.begin() + 2, sums.end(), dag.svo_nodes.begin());
    }
  } else if (root_keys.empty() || (exchange && !exchange->merges)) {
    return dag;
  }
  auto t1 = Clock::now();

  // 2. Reduce the union again, bottom-up, exactly as an in-core build reduces its octree levels: the same
  // hashes of the same (mask, child class, tag) give the same classes, ids and stored orientations. Over
  // ranks, every rank its own union, the classes numbered together.
  Reduced below;
  for (uint32_t l = 1; l <= cube_levels; ++l) {
    dev.finish();  // the scratch of the level below returns to the pool (retired buffers wait for a finish)
    SvoLevel lv = upload_level(dev, u[l]);
    Reduced slots = l == 1 ? Reduced() : gather(dev, u[l], below, symmetric, u[l - 1].mask);
    Reduced r;
    if (merge) {
      r = reduce_level_over_ranks(dev, lv, slots, l == 1, red, *merge, dag.level[l]);
    } else {
      r = reduce ? reduce_level(dev, lv, slots, l == 1, red) : identity_level(dev, lv);
      dag.level[l] = assemble(dev, lv, r, slots, l == 1, red);
    }
    below = std::move(r);
    u[l - 1] = UnionLevel();
  }
  if (merge) {  // the merging rank takes every rank's cube roots, with their classes, in Morton order
    below = cube_roots_at_lead(dev, below, static_cast<uint32_t>(u[cube_levels].size()), symmetric, root_keys,
                               root_node, *merge);
    if (exchange->bytes_exchanged) *exchange->bytes_exchanged += merge->bytes_exchanged;
    if (!exchange->merges) return dag;
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
    dev.finish();
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
                       DagBuildTimes* times, const CubeExchange* exchange) {
  return build_by_cubes(dev, levels, cube_levels, symmetric, true, voxels_of, times, exchange);
}

Dag build_svo_by_cubes(Device& dev, uint32_t levels, uint32_t cube_levels, const CubeVoxels& voxels_of,
                       DagBuildTimes* times, const CubeExchange* exchange) {
  return build_by_cubes(dev, levels, cube_levels, false, false, voxels_of, times, exchange);
}

}  // namespace mv
