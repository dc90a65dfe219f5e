// A point build over ranks writing 3D Tiles (point_ranks.cpp; docs/distributed.md): every rank writes the tiles of
// the subtrees it built into rank 0's temporary folder, rank 0 those above and tileset.json; the same bytes as
// one process. Collective: rank 0's `start` and `finish` (io::Tiles3dShare) and the other ranks'
// write_part_tiles meet.
#pragma once
#include <cstdint>
#include <vector>

#include "io/tiles3d_writer.h"
#include "megavox/point_build.h"
#include "megavox/rank_collectives.h"
#include "omicron.h"

namespace mv::points {

// The tileset options of a point build.
inline io::Tiles3dOptions tiles_options_of(const PointFileOptions& o) { return {o.tiles_minor_version, o.crs, true}; }

// Rank 0, for write_3dtiles: the nodes of `h` the other ranks write (those of their cells, `owner` per cell of
// the top level); `start` sends each rank the folder, the colour shift and which of its top-level nodes the
// join absorbed (absorbed[r]), `finish` waits for every rank's tiles (mv::Error naming a rank that failed).
// `tiles` gets rank 0's own count.
io::Tiles3dShare lead_tiles_share(const RankCollectives& ranks, const PointHierarchy& h, const std::vector<int>& owner,
                                  uint32_t top_level, std::vector<std::vector<bool>> absorbed, uint64_t& tiles);

// Any other rank, once its part went to rank 0: the tiles of its part's nodes (`sorted`: its points in sorted
// order; `grid`: the hierarchy's grid, no nodes) into rank 0's folder. A failure goes to rank 0, which ends the
// run; returns the tiles written.
uint64_t write_part_tiles(const RankCollectives& ranks, const OmicronPart& part, const PointColumns& sorted,
                          PointHierarchy grid, const io::Tiles3dOptions& options, const int64_t lo[3],
                          const int64_t hi[3]);

}  // namespace mv::points
