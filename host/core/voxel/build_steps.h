// Steps of the build shared by `build`, `import` and `export`: voxels -> DAG of a format -> .mvx contents.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "megavox/build.h"
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

// A point cloud (io::is_point_cloud) voxelized, reduced, encoded and written, with its colours: fills r.
void build_cloud(Device& dev, const BuildOptions& o, BuildReport& r, const std::function<void(const std::string&)>& lap,
                 const PlanListener& on_plan);

// Voxel colours into `file` (depth-first RGB24; none when empty), quantized on `dev` to o.colour_bits below 24 (its
// report into r). Returns whether it quantized: the caller times that as a stage of its own.
bool attach_colours(Device& dev, MvxFile& file, std::vector<uint8_t> colours, const BuildOptions& o, BuildReport& r);
// The written colour section's figures into r (nothing without colours).
void report_colours(const MvxFile& file, const MvxColourStats& stats, BuildReport& r);

// DAG nodes over levels >= 2 (bricks counted as nodes).
uint64_t nodes_total(const MvxFile& file);

}  // namespace mv
