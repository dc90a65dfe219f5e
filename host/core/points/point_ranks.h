// A point build spread over MPI ranks (point_ranks.cpp; docs/distributed.md "Point clouds").
#pragma once
#include <functional>

#include "megavox/point_build.h"
#include "megavox/rank_collectives.h"
#include "io/tiles3d_writer.h"

namespace mv::points {

// Collective: every rank calls it with the same options. Rank 0 returns the hierarchy one process builds from
// the same input and options; the other ranks return an empty one. `report` gets this rank's times and counts.
// Rank 0 gathers every point: `check_fits` gets the cloud's header there before any work, and throws where
// the cloud does not fit its memory. With --format 3dtiles the other ranks write their subtrees' tiles before
// they return (point_ranks_tiles.h), and rank 0 gets in `tiles` what its write_3dtiles needs for that.
PointHierarchy build_over_ranks(Device& dev, const PointFileOptions& options, const RankCollectives& ranks,
                                PointFileReport& report, const Progress& progress,
                                const std::function<void(const PointCloudInfo&)>& check_fits,
                                io::Tiles3dShare* tiles);

}  // namespace mv::points
