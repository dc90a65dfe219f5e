// Steps of the build shared by `build`, `import` and `export`: voxels -> DAG of a format -> .mvx contents.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/dag.h"
#include "megavox/mvx.h"

namespace mv {

// The DAG of bricks, or of sorted unique Morton keys, in a 2^levels grid for `format` (svo, svdag, ussvdag or
// ssvdag).
Dag build_dag_for_format(Device& dev, const Bricks& bricks, uint32_t levels, Encoding format,
                         DagBuildTimes* times = nullptr);
Dag build_dag_for_format(Device& dev, const std::vector<uint64_t>& keys, uint32_t levels, Encoding format,
                         DagBuildTimes* times = nullptr);

// Encodes `dag` in `format` with its counts, grid and bounds.
MvxFile mvx_for_dag(const Dag& dag, Encoding format, const GridTransform& grid, const Bounds& bounds);

// DAG nodes over levels >= 2 (bricks counted as nodes).
uint64_t nodes_total(const MvxFile& file);

}  // namespace mv
