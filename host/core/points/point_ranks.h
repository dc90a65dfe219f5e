// A point build spread over MPI ranks (point_ranks.cpp; docs/distributed.md "Point clouds").
#pragma once
#include <functional>

#include "megavox/point_build.h"
#include "megavox/rank_collectives.h"
#include "io/tiles3d_writer.h"
#include "megavox/mvx.h"

namespace mv::points {

// Collective: every rank calls it with the same options. Rank 0 returns the hierarchy one process builds from
// the same input and options; the other ranks return an empty one. `report` gets this rank's times and counts.
// `check_fits` gets the cloud's header on rank 0 before any work, and throws where the cloud does not fit. Rank
// 0 gets the other ranks' top-level candidates alone, and the hierarchy it returns holds the points of its own
// nodes. With --format 3dtiles the other ranks write their subtrees' tiles before they return
// (point_ranks_tiles.h) and `tiles` gets what rank 0's write_3dtiles needs for that; for a .mvx they hand their
// points to rank 0's write_mvx_points (point_ranks_mvx.h), whose `points_share` is what it needs.
PointHierarchy build_over_ranks(Device& dev, const PointFileOptions& options, const RankCollectives& ranks,
                                PointFileReport& report, const Progress& progress,
                                const std::function<void(const PointCloudInfo&)>& check_fits,
                                io::Tiles3dShare* tiles, PointsElsewhere* points_share);

}  // namespace mv::points
