// What an out-of-core mesh build hands build_dag_by_cubes beside its voxels: the ranks' exchange (under
// mpirun), keeping and reusing finished cubes (build --resume), and each cube's voxel colours, which travel and
// are kept with its partial DAG.
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "megavox/build.h"
#include "megavox/rank_collectives.h"
#include "voxel/triangle_buckets.h"

namespace mv {

// Every cube's voxels and their colours, in the order the cubes are taken (Morton order), gathered for the
// depth-first colour array.
struct CubeColours {
  std::vector<uint64_t> keys;
  std::vector<uint32_t> rgb;
  size_t cube_at = 0;  // where the cube being made starts in them (set as each cube starts)
};

// The hooks `o` asks for (nullopt: none: one process, nothing kept). `colours`: the build's, when the mesh is
// coloured, else null. `cubes_resumed` counts the kept cubes reused. What they capture must outlive the build.
// `dealt`, when given: the cubes' estimates the ranks already agreed on (mesh_shares.h), else the buckets'.
std::optional<CubeExchange> cube_hooks(const BuildOptions& o, const TriangleBuckets& buckets, uint32_t per_axis,
                                       CubeColours* colours, uint64_t& cubes_resumed,
                                       const std::vector<uint64_t>* dealt = nullptr);

// Each cube's voxel estimate, rounded, in Morton order of the cubes (what the ranks are dealt by).
std::vector<uint64_t> cube_voxel_estimates(const TriangleBuckets& buckets, uint32_t per_axis);

}  // namespace mv
