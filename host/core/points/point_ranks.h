// A point build spread over MPI ranks (point_ranks.cpp; docs/distributed.md "Point clouds").
#pragma once
#include <functional>

#include "megavox/point_build.h"
#include "megavox/rank_collectives.h"
#include "io/tiles3d_writer.h"

namespace mv::points {

// Collective: every rank calls it with the same options. Rank 0 returns the hierarchy one process builds from
// the same input and options; the other ranks return an empty one. `report` gets this rank's times and counts.
// `check_fits` gets the cloud's header on rank 0 before any work, and throws where the cloud does not fit. For a
// .mvx rank 0 gathers every point. With --format 3dtiles the other ranks write their subtrees' tiles before
// they return (point_ranks_tiles.h), rank 0 gets only the points of the levels above, and in `tiles` what its
// write_3dtiles needs for that; the hierarchy it returns then holds the points of its own nodes alone.
PointHierarchy build_over_ranks(Device& dev, const PointFileOptions& options, const RankCollectives& ranks,
                                PointFileReport& report, const Progress& progress,
                                const std::function<void(const PointCloudInfo&)>& check_fits,
                                io::Tiles3dShare* tiles);

}  // namespace mv::points
