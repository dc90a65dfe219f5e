// The out-of-core merge spread over ranks (docs/distributed.md): each rank holds the union of its own cubes'
// partial DAGs and reduces it, level by level, on its device; each class it finds goes, keyed as the
// reduction sorts it (the brick at level 2, the node hash above), to the rank that owns the key's range (a
// sample sort over the ranks). The owner deduplicates the classes of every rank and numbers its share, the
// numbers go back, so the level above hashes the same ids one process would, and rank 0 gathers the level.
// One process's classes are the distinct keys in key order, wherever the nodes were made, so the DAG is the
// same. Internal to host/dag.
#pragma once
#include <cstdint>
#include <vector>

#include "dag_build_steps.h"
#include "megavox/rank_collectives.h"

namespace mv::detail {

struct RankMerge {
  const RankCollectives& ranks;
  uint64_t bytes_exchanged = 0;  // sent to and received from the other ranks
};

// Collective: the classes of this rank's union level `lv` (it may have no nodes) with ids over every rank's
// (per node in r.id; level 1, `leaf`: the class ranks and masks), given `slots`, those of the level below
// from gather(). Rank 0 gets the whole DAG level in `level`.
Reduced reduce_level_over_ranks(Device& dev, const SvoLevel& lv, const Reduced& slots, bool leaf,
                                const Reduction& red, RankMerge& m, DagLevel& level);

// Collective, after the cubes' top level: every rank's cube roots at rank 0, in Morton order. There `keys`
// and `nodes` become every rank's roots (nodes indexing the classes returned: each root's class id and, with
// symmetry, orientation); the other ranks get nothing back. `top`: the top level's classes, `top_n` nodes.
Reduced cube_roots_at_lead(Device& dev, const Reduced& top, uint32_t top_n, bool symmetric,
                           std::vector<uint64_t>& keys, std::vector<uint32_t>& nodes, RankMerge& m);

}  // namespace mv::detail
