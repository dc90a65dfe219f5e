// megavox — sparse voxel octree levels and their reduction to a DAG of distinct subtrees.
//
// Levels count from the bottom (the convention of the public voxcom tools): level 0 = voxels, level 1 =
// 2x2x2 masks, level 2 = 4x4x4 bricks, ..., level L = the root of a 2^L grid. Octants are Morton octants
// (bit 0 = x, bit 1 = y, bit 2 = z); encoders convert to their format's order.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "megavox/error.h"

#include "megavox/bricks.h"
#include "megavox/dag_types.h"
#include "megavox/device.h"
#include "megavox/rank_collectives.h"

namespace mv {

struct DagBuildTimes {
  double svo_seconds = 0;     // voxels -> SVO levels
  double reduce_seconds = 0;  // SVO -> DAG
};

// Builds the octree levels of 4^3 bricks (megavox/bricks.h; level 2 is the bricks, level 1 their 2^3 masks)
// and reduces each level, bottom-up, to its distinct subtrees: the minimal DAG. Runs on the device; per-level
// results come back to the host.
Dag build_svdag(Device& dev, const Bricks& bricks, uint32_t levels, DagBuildTimes* times = nullptr);
// The same from sorted, unique voxel keys (64-bit Morton codes of a 2^levels grid).
Dag build_svdag(Device& dev, const std::vector<uint64_t>& voxels, uint32_t levels, DagBuildTimes* times = nullptr);

// The same octree reduced up to the 8 axis reflections: subtrees that are mirror images of each other share
// one node and pointers carry reflection tags; exact (the stabilizer method), so no symmetry is missed. The
// root is stored in the model's own orientation.
Dag build_ssvdag(Device& dev, const Bricks& bricks, uint32_t levels, DagBuildTimes* times = nullptr);
Dag build_ssvdag(Device& dev, const std::vector<uint64_t>& voxels, uint32_t levels, DagBuildTimes* times = nullptr);

// The bricks (global brick keys) of the cube [x, x + size)^3... of the grid.
using CubeVoxels = std::function<Bricks(uint32_t x, uint32_t y, uint32_t z, uint32_t size)>;

// Thrown by build_dag_by_cubes when one cube's voxels or partial DAG do not fit device memory (smaller cubes
// may; the merge that follows needs memory for whole merged levels and fails with a plain DeviceMemoryError).
class CubeMemoryError : public DeviceMemoryError {
 public:
  using DeviceMemoryError::DeviceMemoryError;
};

// An out-of-core build spread over processes (host/dist): the process that makes each cube's partial DAG, and
// how the parts are merged: over the processes (a reduced build) or by the one that receives them all (the
// plain octree). Cubes go in Morton order; each is made by its owner.
// Also how a build keeps its cubes to resume (below).
struct CubeExchange {
  std::function<bool(uint64_t cube)> mine;  // this process voxelizes and reduces the cube (null: every cube)
  bool merges = true;  // this process merges every part (the others stop once theirs are sent)
  // A process that does not merge: the part it made of its cube (null: the cube is empty), with the builder's
  // payload for it.
  std::function<void(uint64_t cube, const Dag* part, std::vector<uint8_t> payload)> send;
  // The merging process, a cube another made: its part (nullopt: empty), in Morton order, and its payload.
  std::function<std::optional<Dag>(uint64_t cube, std::vector<uint8_t>& payload)> receive;
  // Set by the builder when a cube brings more than its part (its voxels' colours): taken after a cube made
  // here that another process merges, and handed back, in Morton order, where it is merged.
  std::function<std::vector<uint8_t>()> take_payload;
  std::function<void(std::vector<uint8_t>& payload)> put_payload;
  // Set for a build that keeps its cubes (build --resume): a cube an earlier run of the same build kept comes
  // back from `load` (its payload through put_payload) instead of being made; a cube made here goes to `keep`
  // with the payload peek_payload gives (the cube just made's, left in place).
  std::function<std::optional<Dag>(uint64_t cube, std::vector<uint8_t>& payload)> load;
  std::function<void(uint64_t cube, const Dag& part, std::vector<uint8_t> payload)> keep;
  std::function<std::vector<uint8_t>()> peek_payload;
  // Set for a build over ranks: a reduced build (not the plain octree) then merges over them. Each rank
  // merges the parts it made, the merged levels are reduced together (dag/merge_over_ranks.h), and parts
  // never travel: only payloads do, sent by their maker in Morton order and received by the merging process
  // (`merges`), which alone returns the DAG. `bytes_exchanged` counts what the merge moved.
  const RankCollectives* collectives = nullptr;
  std::function<void(uint64_t cube, std::vector<uint8_t> payload)> send_payload;
  std::function<void(uint64_t cube, std::vector<uint8_t>& payload)> receive_payload;
  uint64_t* bytes_exchanged = nullptr;
};

// Out-of-core: the grid is split into cubes of 2^cube_levels voxels per side, taken one at a time in Morton
// order (only one cube's voxels are ever in memory), each reduced on its own; the partial DAGs are then
// merged and reduced again bottom-up. The result is identical, byte for byte once encoded, to the in-core
// build of all the voxels. `times` counts the cubes as the octree stage and the merge as the reduction.
// With `exchange`, only the cubes it says are made here; a process that does not merge returns an empty Dag.
Dag build_dag_by_cubes(Device& dev, uint32_t levels, uint32_t cube_levels, bool symmetric, const CubeVoxels& voxels_of,
                       DagBuildTimes* times = nullptr, const CubeExchange* exchange = nullptr);

// The octree itself, unreduced, in the same form (each level's nodes in key order).
Dag build_svo(Device& dev, const Bricks& bricks, uint32_t levels, DagBuildTimes* times = nullptr);
Dag build_svo(Device& dev, const std::vector<uint64_t>& voxels, uint32_t levels, DagBuildTimes* times = nullptr);

// The octree out of core, cube by cube: the same as build_svo of all the voxels (host memory holds the whole
// octree; the device one cube and one merged level at a time).
Dag build_svo_by_cubes(Device& dev, uint32_t levels, uint32_t cube_levels, const CubeVoxels& voxels_of,
                       DagBuildTimes* times = nullptr, const CubeExchange* exchange = nullptr);


}  // namespace mv
