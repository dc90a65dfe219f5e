// The steps of a DAG build on the device, shared by the in-core build (dag_build.cpp), the reduction of one
// level (dag_reduce.cpp) and the out-of-core merge of cubes (dag_by_cubes.cpp): the octree level as the
// device holds it, the classes a reduction finds, and the calls that make, reduce and read back a level.
// Internal to host/dag; not a public API.
#pragma once
#include <chrono>
#include <cstdint>
#include <vector>

#include "common/ssvdag.h"
#include "megavox/dag.h"
#include "megavox/device.h"

namespace mv::detail {

using Clock = std::chrono::steady_clock;
inline constexpr uint32_t kLocal = 64;

// The octree level l as the device holds it while building: node keys, child masks, first children.
struct SvoLevel {
  uint32_t n = 0;
  Buffer keys, mask, first;
};

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

// How a build reduces its levels: plainly, or up to reflections with the mask table made once per build.
struct Reduction {
  bool symmetric = false;
  Buffer mask_table;  // symmetric only
};

// dag_reduce.cpp

Reduction make_reduction(Device& dev, bool symmetric);

// What a reduction spread over ranks (dag_merge_ranks.cpp) needs of each rank's: the classes' sort keys, in
// id order (the 64-bit brick, canonical with symmetry, at level 2; the node hash above), and the hash seed,
// tried first and then the one that held (a seed holds when no two different nodes share a hash).
struct ClassKeys {
  uint32_t seed = 1;
  std::vector<uint64_t> keys;
};

// A test hook: MEGAVOX_TEST_HASH_BITS=k (1 to 64) keeps only the low k bits of the node hashes made with the
// first seed, so that tests meet the hash collisions (and the retries with the next seed) that 64-bit hashes
// never show them; each one is then reported on stderr. Returns the high bits to clear for `seed`.
uint32_t test_hash_drop(uint32_t seed);
void report_test_collision(const char* where, uint32_t seed);

// The classes of level `lv` given those of the level below; `leaf`: lv is level 1.
Reduced reduce_level(Device& dev, const SvoLevel& lv, const Reduced& below, bool leaf, const Reduction& red,
                     ClassKeys* keys = nullptr);

// No reduction (the plain octree): every node is its own class.
Reduced identity_level(Device& dev, const SvoLevel& lv);

// dag_build.cpp

// The octree level above the sorted unique keys `keys`.
SvoLevel build_parents(Device& dev, const Buffer& keys, uint32_t n);

// The DAG level in id order: each representative in its stored orientation (reflected by its T* for the
// SSVDAG) with its children's (id, tag) in octant order.
DagLevel assemble(Device& dev, const SvoLevel& lv, const Reduced& r, const Reduced& below, bool leaf,
                  const Reduction& red);

// After the root level: wait, store the root unreflected, report the times.
void finish_build(Device& dev, Dag& dag, const Reduced& root, const Reduction& red, Clock::time_point t0,
                  Clock::time_point t1, DagBuildTimes* times);

// The whole build of `bricks` in core; `shared`: a Reduction made by the caller for many builds (the
// out-of-core cubes), else one is made here.
Dag build_dag(Device& dev, const Bricks& bricks, uint32_t levels, bool symmetric,
              DagBuildTimes* times, bool reduce = true, const Reduction* shared = nullptr);

}  // namespace mv::detail
