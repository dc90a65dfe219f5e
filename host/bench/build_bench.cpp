#include "build_bench.h"

#include <algorithm>
#include <filesystem>

#include "peak_rss.h"
#include "scratch_dir.h"
#include "megavox/error.h"
#include "stopwatch.h"

namespace mv::bench {

namespace {

// Stages of build_mvx's report that come before the DAG reduction (build_pipeline.cpp names them).
bool voxelization_stage(const std::string& name) {
  return name == "read" || name == "voxelize" || name == "voxelize+cubes";
}

double difference(uint64_t ours, uint64_t theirs) {
  return theirs ? (double(ours) - double(theirs)) / double(theirs) : 0;
}

}  // namespace

BuildBenchResult run_build_bench(Device& dev, BuildOptions o, int repeats, const PlainRead& read) {
  BuildBenchResult r;
  r.read = read;
  ScratchDir scratch;
  const bool keep = !o.output.empty();
  if (!keep) o.output = scratch.file("bench.mvx");
  for (int rep = 0; rep < std::max(repeats, 1); ++rep) {
    if (!keep) std::filesystem::remove(o.output);  // each run writes the file anew, as a user's build does
    const auto t = Clock::now();
    BuildReport report = build_mvx(dev, o);
    const double seconds = since(t);
    r.wall_seconds.push_back(seconds);
    if (rep == 0 || seconds < r.best_seconds) {
      r.best_seconds = seconds;
      r.report = std::move(report);
    }
  }
  if (!keep) r.report.output.clear();
  for (const auto& s : r.report.seconds)
    if (voxelization_stage(s.name)) r.voxelize_seconds += s.seconds;
  if (r.voxelize_seconds > 0) {
    r.voxels_per_s = double(r.report.voxels) / r.voxelize_seconds;
    r.triangles_per_s = double(r.report.triangles) / r.voxelize_seconds;
  }
  r.peak_rss_bytes = peak_rss_bytes();
  r.read_ratio = r.read.seconds > 0 ? r.best_seconds / r.read.seconds : 0;
  return r;
}

PeerComparison compare_with_peer(const BuildBenchResult& r, const std::vector<PeerRun>& runs, double extra_seconds) {
  if (runs.empty()) throw Error("compare_with_peer: no peer runs");
  PeerComparison c;
  c.peer = *std::min_element(runs.begin(), runs.end(),
                             [](const PeerRun& a, const PeerRun& b) { return a.wall_seconds < b.wall_seconds; });
  for (const PeerRun& run : runs) c.peer.max_rss_bytes = std::max(c.peer.max_rss_bytes, run.max_rss_bytes);
  const bool symmetric = r.report.format == "ssvdag" || r.report.format == "ussvdag";
  c.counts_from = symmetric ? "ssvdag" : "svdag";
  const PeerCounts& counts = symmetric ? c.peer.ssvdag : c.peer.svdag;
  c.wall_ratio = (r.best_seconds + extra_seconds) / c.peer.wall_seconds;
  c.rss_ratio = c.peer.max_rss_bytes ? double(r.peak_rss_bytes) / double(c.peer.max_rss_bytes) : 0;
  c.voxel_difference = difference(r.report.voxels, counts.voxels);
  c.node_difference =
      difference(r.report.nodes_total, r.report.format == "svo" ? counts.svo_nodes : counts.dag_nodes);
  return c;
}

}  // namespace mv::bench
