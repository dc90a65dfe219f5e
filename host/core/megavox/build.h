// megavox — the main job: a mesh on disk to an encoded voxel DAG in a .mvx file.
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "megavox/colour_quantize.h"
#include "megavox/dag.h"
#include "megavox/device.h"
#include "megavox/mvx.h"
#include "megavox/rank_collectives.h"
#include "megavox/voxelize.h"

namespace mv {

// Meshes above this many voxels per side build out of core by default. One constant for BuildOptions, the
// CLI's --cube and the C API's cube 0 (and so the service, which builds through the C API), so that the same
// build asked of any of them runs the same way.
inline constexpr uint32_t kDefaultCube = 1024;

// A mesh in the caller's memory: 3 floats per vertex, 3 indices per triangle (read in place, not copied).
struct MeshArrays {
  std::span<const float> positions;
  std::span<const uint32_t> indices;
  std::span<const uint32_t> colours;  // per vertex 0xBBGGRR (8-bit), or empty
};

// A build spread over processes (host/dist, under mpirun). Out of core, every process buckets the triangles;
// `exchange` then gets each cube's voxel estimate (TriangleBuckets::voxel_estimate), in Morton order, and says
// which cubes this process makes and how their partial DAGs are merged (megavox/dag.h: over the ranks, or at
// the process that `writes`, which writes the output); in core it alone builds.
struct BuildRanks {
  std::function<CubeExchange(const std::vector<uint64_t>& cube_voxels)> exchange;
  bool writes = true;
  // Set: the ranks read shares of the mesh's faces where the file allows, and swap triangles by cube owner
  // (voxel/mesh_shares.h); unset: every rank reads the whole mesh.
  const RankCollectives* collectives = nullptr;
};

// Voxel colours: automatic = rgb when the input has colour; rgb on an input without colour is an error.
enum class Attributes { automatic, none, rgb };

struct BuildOptions {
  std::string input;         // a mesh: PLY (streamed) or anything assimp reads (OBJ, glTF, FBX, STL, ...),
                             // or an OpenVDB .vdb volume (one VDB voxel = one voxel)
  std::string output;        // the .mvx to write (checked before any work: io/output_path.h)
  bool no_clobber = false;  // refuse to replace an existing output (an input is never replaced)
  uint32_t resolution = 0;   // voxels per axis, a power of two; 0: 1024 for meshes, the smallest fit for .vdb
  std::string grid;          // .vdb: the grid to read (empty: the first)
  // Meshes above this resolution build out of core, one cube of this many voxels per side at a time
  // (a power of two); 0 = always in core.
  uint32_t cube = kDefaultCube;
  Encoding encoding = Encoding::svdag;
  GridPlacement placement;  // meshes: where the grid sits (a .vdb keeps its index space)
  Voxelizer::Rule voxelize = Voxelizer::Rule::kConservative;  // meshes: 26-separating or thin (6-separating)
  // Host RAM budget in bytes (0: half the physical RAM). A build whose triangles or voxel keys would pass it
  // stops with an error naming what it needs (nothing is written).
  uint64_t memory = 0;
  Attributes attributes = Attributes::automatic;  // point clouds (docs/colour.md)
  uint32_t colour_bits = 24;  // below 24: quantized to at most 2^bits colours (megavox/colour_quantize.h)
  // Instead of reading `input`: this mesh (then `input` only names it in messages).
  const MeshArrays* mesh = nullptr;
  const BuildRanks* ranks = nullptr;  // set: one of the processes of a distributed build
  // Set (build --resume): a build in cubes keeps each finished cube in this folder and reuses those a run of
  // the same build (the same fingerprint) kept there; the folder goes once the output is written.
  std::string resume_dir;
  uint64_t resume_fingerprint = 0;
  // How the file is paged (megavox/mvx.h; an ssvdag always in level order).
  MvxPaging paging;
};

// What a build will do, stated before the heavy work: the grid, in core or in cubes, and estimates of its
// size and memory. The estimates come from the mesh's surface alone (its triangles' area projected on the
// axes, over the voxel's face area), so a build clipped by --bounds or a mesh folded finer than a voxel counts
// fewer voxels than estimated; a .vdb's voxels are counted, not estimated.
struct BuildPlan {
  uint32_t resolution = 0;
  double voxel_size = 0;
  double origin[3] = {0, 0, 0};
  uint64_t triangles = 0;           // meshes: the faces read to find the bounds
  double surface_area = 0;          // meshes: the triangles' area, in the mesh's units squared
  bool out_of_core = false;
  uint32_t cube = 0;                // out of core: the cube side (voxels)
  uint64_t cubes = 0;               // out of core: cubes in the grid, (resolution / cube)^3
  uint64_t cubes_with_surface = 0;  // out of core: estimated cubes the surface meets (the ones built)
  uint64_t voxels = 0;              // estimated (counted for a .vdb)
  uint64_t output_bytes = 0;        // estimated size of the encoded DAG
  uint64_t host_bytes = 0;          // estimated peak host memory
  uint64_t device_bytes = 0;        // estimated peak device memory
  std::vector<std::string> warnings;  // estimates past the budgets or past what a build finishes quickly
};

struct BuildReport {
  std::string input, output, format;
  uint64_t cubes_resumed = 0;  // cubes an earlier run kept (build --resume), not made again
  uint32_t resolution = 0;
  uint64_t triangles = 0;  // 0 for a .vdb input
  uint64_t points = 0;     // a point cloud input: its points read (and inside the grid)
  std::string attributes = "none";  // "rgb" when the file carries voxel colours
  uint64_t colour_entries = 0;      // colours stored: voxels and inner nodes
  uint64_t colour_bytes = 0;        // the colour section's bytes, head included
  std::string colour_format;        // "raw" or "palette": the smaller, as stored
  uint64_t colour_palette_bytes = 0;    // the palette's section bytes, also when raw was smaller
  double colour_palette_seconds = 0;    // palette selection on the host (part of the write)
  ColourQuantizeReport colour_quantize; // bits 24: not quantized
  double colour_bits_per_voxel = 0; // colour bits (inner nodes' included) / voxels
  std::string vdb_grid, vdb_class;  // the .vdb grid read and its class
  uint32_t cube = 0;                // out of core: the cube side used; 0 = in core
  uint64_t spilled_bytes = 0;       // out of core: triangle bytes spilled to a temporary file (over --memory)
  uint64_t bytes_read = 0;          // over ranks reading shares of the faces: the input bytes this rank's spans
  uint64_t bytes_exchanged = 0;     // then: triangle bytes it sent to and received from other ranks
  uint64_t vertex_scratch_bytes = 0;  // PLY vertex positions kept in a mapped scratch file (over --memory)
  uint32_t cube_retries = 0;        // times the cubes were halved because a cube did not fit device memory
  std::string grid_origin, voxelize;  // meshes: the placement and voxelization rule used
  GridTransform grid;                 // world -> grid, as stored in the .mvx
  uint64_t voxels = 0;
  std::vector<uint64_t> svo_nodes;       // index = level (0 = voxels, 1 = 2^3 masks, 2 = 4^3 bricks, ...)
  std::vector<uint64_t> nodes_per_level; // the DAG's, same indexing
  uint64_t nodes_total = 0;              // DAG nodes over levels >= 2 (bricks counted as nodes)
  uint64_t bytes = 0;                    // the encoded DAG
  double bits_per_voxel = 0;
  struct Stage {
    std::string name;
    double seconds;
  };
  std::vector<Stage> seconds;  // per stage, in order
  BuildPlan plan;              // as announced before the heavy work
};

// Called with a stage name and the fraction done (0..1), from the calling thread.
using Progress = std::function<void(const std::string& stage, double fraction)>;

// Called once, with the plan, after the input's bounds are read and before the voxels are built.
using PlanListener = std::function<void(const BuildPlan&)>;

BuildReport build_mvx(Device& dev, const BuildOptions& options, const Progress& progress = {},
                      const PlanListener& on_plan = {});

// The plan alone: reads the mesh's faces once (no device work). For a .vdb, reads its voxels.
BuildPlan plan_build(const BuildOptions& options);

// The output, resolved and checked as io/output_path.h says (not an input, not a FIFO or device, its folder
// there and writable, ...): the path to write. The call above makes it first; a caller that opens a device
// first (the CLI) makes it before, so a wrong -o costs nothing. Throws mv::Error.
std::string check_output(const BuildOptions& options);

// Half the machine's physical RAM, divided among the processes set_host_memory_share names: the default --memory.
uint64_t default_host_memory();
// The processes of one run on this machine (the ranks of an MPI run on one node) that share its default budget.
void set_host_memory_share(uint32_t processes);

// "16K" -> 16384, "2048" -> 2048; throws mv::Error unless a power of two in [2, 2^21].
uint32_t parse_resolution(const std::string& text);

}  // namespace mv
