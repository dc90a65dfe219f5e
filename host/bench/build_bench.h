// `megavox bench build`: `megavox build` itself (build_mvx, in core or out of core by --cube), timed run by run,
// with its stages, voxelization rates, the process's peak memory and the ratio to a plain read of the mesh;
// and the comparison with a peer's run on the same input.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "plain_read.h"
#include "voxcom_peer.h"
#include "megavox/build.h"
#include "megavox/device.h"

namespace mv::bench {

struct BuildBenchResult {
  BuildReport report;                // of the fastest run
  std::vector<double> wall_seconds;  // build_mvx of every run, in order (the first also builds the kernels)
  double best_seconds = 0;
  // The fastest run's stages up to the DAG reduction (in core: voxelize, which reads the mesh too; out of
  // core: read and voxelize+cubes, which holds the cubes' own reductions), and voxels, triangles per second.
  double voxelize_seconds = 0, voxels_per_s = 0, triangles_per_s = 0;
  uint64_t peak_rss_bytes = 0;  // this process's peak so far (getrusage RUSAGE_SELF): device runtime included
  PlainRead read;               // the mesh file read plainly (bench::plain_read)
  double read_ratio = 0;        // best_seconds / read.seconds: the build against the floor of any tool
};

// Builds `o` `repeats` times on `dev` (o.output empty: a scratch file, removed); `read` is o.input's plain read.
BuildBenchResult run_build_bench(Device& dev, BuildOptions o, int repeats, const PlainRead& read);

// megavox against the peer, both on the same input (`extra_seconds`: what megavox paid besides the builds
// that a peer's process pays inside its wall time, i.e. opening the device).
struct PeerComparison {
  PeerRun peer;  // the fastest run, with the largest peak RSS of all runs
  std::string counts_from;                   // the peer's STATS line matching --format: "svdag" or "ssvdag"
  double wall_ratio = 0, rss_ratio = 0;      // megavox / peer
  double voxel_difference = 0;               // (megavox - peer) / peer voxels
  double node_difference = 0;                // the same for DAG nodes over levels >= 2 (svo: octree nodes)
};
PeerComparison compare_with_peer(const BuildBenchResult& r, const std::vector<PeerRun>& runs, double extra_seconds);

}  // namespace mv::bench
