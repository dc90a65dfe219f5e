// `megavox bench reductions`: one octree reduced to an SVDAG and to an SSVDAG, their times and size ratios.
#pragma once
#include <cstdint>
#include <string>

#include "megavox/device.h"

namespace mv::bench {

struct ReductionBenchResult {
  std::string mesh;
  uint32_t resolution = 0;
  uint64_t triangles = 0, voxels = 0;
  double voxelize_seconds = 0;  // triangles -> sorted unique voxel keys (on the device)
  double svo_seconds = 0;       // voxels -> octree levels, the same for both reductions (best of the two)
  double svdag_seconds = 0;     // octree -> SVDAG, best of the repeats
  double ssvdag_seconds = 0;    // octree -> SSVDAG, best of the repeats (alternating with the SVDAG runs)
  uint64_t svdag_nodes = 0, ssvdag_nodes = 0;  // levels >= 2
  uint64_t svdag_bytes = 0, ussvdag_bytes = 0, ssvdag_bytes = 0;
  double svdag_voxels_per_s = 0;   // voxels / svdag_seconds
  double ssvdag_voxels_per_s = 0;  // voxels / ssvdag_seconds
  double time_ratio = 0;           // ssvdag_seconds / svdag_seconds (best over best)
  double time_ratio_median = 0;    // median over the back-to-back pairs of SSVDAG time / SVDAG time
  double byte_ratio = 0;           // ussvdag_bytes / svdag_bytes (same 32-bit layout)
  double compact_byte_ratio = 0;   // ssvdag_bytes / svdag_bytes: the thesis's SSVDAG/SVDAG size ratio
  double read_gb_per_s = 0;        // the mesh file read plainly, the floor of any tool that reads it
};

ReductionBenchResult run_reduction_bench(Device& dev, const std::string& mesh, uint32_t resolution, int repeats = 5);

}  // namespace mv::bench
