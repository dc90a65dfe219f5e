// megavox — building a point cloud's LOD hierarchy on a Device (OMiCroN's bottom-up construction,
// docs/ARCHITECTURE.md "Point clouds").
#pragma once
#include <cstdint>
#include <functional>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "megavox/build.h"
#include "megavox/device.h"
#include "megavox/points.h"
#include "megavox/primitives.h"
#include "megavox/rank_collectives.h"

namespace mv {

struct PointBuildOptions {
  uint32_t depth = 0;                // the leaf level (1-21); 0: point_depth_for(points, max_node_points)
  uint32_t max_node_points = 16384;  // a subtree of at most this many points is one leaf; caps representatives
  uint32_t grid_bits = 6;            // an inner node keeps one point per cell of a 2^grid_bits grid over its cube
  uint64_t prefix_points = uint64_t{1} << 20;  // sorted points handed to the builder per step (its cut advances)
  // Where the in-place hybrid sort runs, it hands the builder its top-digit buckets in this many ranges, each
  // while the next one sorts (radix_sort's SortedPrefix); 1: the builder starts once the sort has ended.
  uint32_t sort_ranges = 8;
  // When set: called after a step once checkpoint_points more sorted points are in leaves, with the finished
  // part as a forest (the subtrees whose roots have no parent yet; roots holds their node indices), points
  // gathered: a picture while building (OMiCroN's oblique cut).
  std::function<void(const PointHierarchy& partial, const std::vector<uint32_t>& roots)> on_checkpoint;
  uint64_t checkpoint_points = 0;
  // When set, checkpoints hand over OMiCroN's rendering front instead of the forest: the nodes a frame draws,
  // kept across the build and updated after every step (placeholders, substitution, prune and branch; see
  // host/core/points/omicron_front.h), as a flat `partial` whose nodes are all leaves in Morton order (roots lists
  // them; its nodes_per_level counts the nodes made so far). front_fine_enough(grid, level, prefix) says a node is dense enough on screen to be drawn instead of its
  // children; `grid` carries the hierarchy's grid (source, cube, shift, grid bits) and no nodes.
  std::function<bool(const PointHierarchy& grid, uint32_t level, uint64_t prefix)> front_fine_enough;
};

// After each step of the build: how far the cut has come.
struct PointBuildProgress {
  uint64_t points_formed = 0;  // sorted points in leaves
  uint64_t points_total = 0;
  uint64_t nodes = 0;          // nodes made so far, on every level
};

struct PointBuildReport {
  double codes_seconds = 0, sort_seconds = 0, build_seconds = 0, gather_seconds = 0;
  SortReport sort;
  uint64_t steps = 0;        // concatenate + fix steps
};

// The density rule for the leaf level: a surface's points spread over about 4^l cells of level l, so
// ceil(log4(points / max_node_points)) is the level where an average leaf holds max_node_points; two levels
// more leave room for denser spots, and leaf collapse merges the sparse ones back up. Clamped to 1-21.
uint32_t point_depth_for(uint64_t points, uint32_t max_node_points);

// Sorts `points` by Morton code on the device and builds the hierarchy from the sorted stream, calling
// `progress` after every step. The columns are consumed (their memory is reused).
PointHierarchy build_point_hierarchy(Device& dev, PointColumns&& points, const PointCloudInfo& info,
                                     const PointBuildOptions& options, PointBuildReport* report = nullptr,
                                     const std::function<void(const PointBuildProgress&)>& progress = {});

}  // namespace mv

namespace mv {

// What a point build writes: a .mvx point hierarchy, or a 3D Tiles folder.
enum class PointOutput { mvx, tiles3d };

// `megavox points build`: a point file (PLY, LAS) to a .mvx point hierarchy or a 3D Tiles folder.
struct PointFileOptions {
  std::string input, output;
  PointOutput format = PointOutput::mvx;
  PointBuildOptions build;
  uint64_t memory = 0;         // host budget in bytes; 0 = default_host_memory()
  bool carry_extra_bytes = true;
  // --format 3dtiles: 3D Tiles 1.1 (.glb tiles, placed on the globe when the cloud has a CRS) or 1.0 (.pnts).
  int tiles_minor_version = 1;
  // --format 3dtiles: the CRS to place the tileset with ("EPSG:N", WKT), over the one the input declares.
  std::string crs;
  // LAS and LAZ: only the points in this box (world min x, y, z, max x, y, z); a COPC file decodes only the
  // chunks whose node meets it.
  std::optional<std::array<double, 6>> bounds;
  uint64_t run_points = 0;     // > 0: sort out of core in runs of this many points, whatever the budget (tests)
  bool no_clobber = false;  // refuse to replace an existing output (an input is never replaced)
  // Set: the cloud is these arrays (the C API's build from memory), named `input` in messages; never out of core.
  const PointArrays* arrays = nullptr;
  // Set with more than one rank: this process is one rank of a build spread over several (mpirun); rank 0
  // writes the output, the bytes one process writes (docs/distributed.md).
  const RankCollectives* ranks = nullptr;
};

// One rank's share of a build spread over ranks.
struct PointRankCounts {
  uint64_t points_read = 0;      // its slice of the input
  uint64_t points_built = 0;     // in the cells dealt to it, whose subtrees it built
  uint64_t bytes_read = 0;       // of the input file: its slice's share of the file (all before it too where the
                                 // format cannot seek to a point)
  uint64_t bytes_exchanged = 0;  // sent to and received from other ranks
  double join_seconds = 0;       // rank 0: the levels above the dealt cells, and the gather into node order
  uint64_t tiles_written = 0;    // --format 3dtiles: the tiles this rank wrote
};

struct PointFileReport {
  std::string input, output, format, input_format;
  uint64_t points_in = 0, points_kept = 0, points_dropped = 0, nodes = 0, stored_points = 0;
  uint32_t depth = 0;
  std::vector<uint64_t> nodes_per_level;
  double read_seconds = 0, sort_seconds = 0, build_seconds = 0, write_seconds = 0, total_seconds = 0;
  double points_per_second = 0;  // points in over the total
  bool out_of_core = false;      // sorted in runs on disk (the cloud did not fit --memory), then merged
  uint64_t sort_runs = 1;
  PointBuildReport build;
  PointRankCounts ranks;  // a build over ranks: this rank's counts
};

// Every point of a cloud file (PLY, LAS) in memory, and what the file says of them.
PointColumns read_point_file(const std::string& path, PointCloudInfo& info, bool carry_extra_bytes = true,
                             const Progress& progress = {});

// Progress stages: "read", "build", "write", with the fraction done.
PointFileReport build_points_file(Device& dev, const PointFileOptions& options, const Progress& progress = {});
// The output, resolved and checked as io/output_path.h says (not an input, not a FIFO or device, its folder
// there and writable, ...): the path to write. The call above makes it first; a caller that opens a device
// first (the CLI) makes it before, so a wrong -o costs nothing. Throws mv::Error.
std::string check_output(const PointFileOptions& options);

}  // namespace mv
