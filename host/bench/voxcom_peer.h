// The build benchmarks' peer: voxcom's CPU voxelizer and DAG builder (../shared/peers/voxcom, built apart,
// never linked), run as a child process on the same mesh for its wall time, peak memory and counts.
#pragma once
#include <cstdint>
#include <string>

#include "megavox/build.h"

namespace mv::bench {

// One level-total line of the peer's stats patch: `STATS <tag> total: voxels=V svo_nodes=N dag_nodes=M`
// (nodes over levels >= 2, as megavox counts them).
struct PeerCounts {
  uint64_t voxels = 0, svo_nodes = 0, dag_nodes = 0;
};

struct PeerRun {
  double wall_seconds = 0;
  uint64_t max_rss_bytes = 0;  // the child's ru_maxrss (wait4)
  PeerCounts svdag, ssvdag;
};

// Where scripts/bench.sh builds it: peers/voxcom/voxelizer next to this executable (build/).
std::string default_voxcom_path();

// Empty when voxcom builds the same voxels as `o` (thin rule, grid at the mesh's min corner); otherwise why
// not, in a few words.
std::string voxcom_mismatch(const BuildOptions& o);

// Runs voxcom's voxelizer on `mesh` at `resolution` (a power of two), writing its SVO, SVDAG and SSVDAG into a
// temporary folder removed afterwards (all three, as its README times it). Throws mv::Error when it fails or
// prints no STATS lines, with the end of its output.
PeerRun run_voxcom(const std::string& binary, const std::string& mesh, uint32_t resolution);

// Parses the two STATS total lines out of the peer's output (throws mv::Error when one is missing).
void parse_voxcom_stats(const std::string& output, PeerRun& run);

}  // namespace mv::bench
