// `megavox bench build`: `megavox build` timed on a mesh, beside a plain read of the file and, where it builds
// the same voxels, voxcom's voxelizer on the same input in the same run.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "bench_ranks.h"
#include "build_bench.h"
#include "stopwatch.h"
#include "voxcom_peer.h"
#include "megavox/error.h"
#include "build_args.h"
#include "cli_common.h"

namespace mv::cli {

namespace {

struct BenchBuildArgs : BuildArgs {
  std::string output, peer = bench::default_voxcom_path();
  int repeats = 1, ranks = 0;
  bool json = false, no_peer = false;
};

struct PeerOutcome {
  std::string status;  // "ran", or one line saying why it did not
  std::vector<bench::PeerRun> runs;
};

// The peer's runs on the same input, or why there are none (not wanted, other voxels, not built).
PeerOutcome run_peer(const BenchBuildArgs& a, const BuildOptions& o) {
  if (a.no_peer) return {"peer: not run (--no-peer)", {}};
  if (std::string why = bench::voxcom_mismatch(o); !why.empty()) return {"peer: not run: " + why, {}};
  if (!std::filesystem::exists(a.peer))
    return {"peer: voxcom not built (" + a.peer + " is missing); build it with `bash ../shared/peers/voxcom/build.sh " +
                "build/peers/voxcom` (scripts/bench.sh does when ../shared/peers/voxcom exists)",
            {}};
  PeerOutcome out{"ran", {}};
  try {
    for (int rep = 0; rep < a.repeats; ++rep)
      out.runs.push_back(bench::run_voxcom(a.peer, o.input, o.resolution ? o.resolution : 1024));  // build's default
  } catch (const mv::Error& e) {  // the peer's failure is a line of the report, not the end of megavox's benchmark
    return {std::string("peer: ") + e.what(), {}};
  }
  return out;
}

double mib(uint64_t bytes) { return double(bytes) / (1 << 20); }

void print_table(const bench::BuildBenchResult& r, const std::string& device, double open_seconds,
                 const PeerOutcome& peer, const bench::PeerComparison* c) {
  const BuildReport& b = r.report;
  std::string cubes = b.cube ? "out of core, cubes of " + std::to_string(b.cube) + "^3" : "in core";
  if (b.cube_retries) cubes += " (halved " + std::to_string(b.cube_retries) + "x to fit device memory)";
  std::printf("%s at %u^3 on %s: %s, %s, grid origin %s, %s\n", b.input.c_str(), b.resolution, device.c_str(),
              b.format.c_str(), b.voxelize.c_str(), b.grid_origin.c_str(), cubes.c_str());
  std::printf("  %llu triangles, %llu voxels, %llu DAG nodes (levels >= 2), %llu bytes\n",
              (unsigned long long)b.triangles, (unsigned long long)b.voxels, (unsigned long long)b.nodes_total,
              (unsigned long long)b.bytes);
  std::printf("  build %.3f s (best of %zu:", r.best_seconds, r.wall_seconds.size());
  for (double s : r.wall_seconds) std::printf(" %.3f", s);
  std::printf("), device opened in %.3f s; stages:", open_seconds);
  for (const auto& s : b.seconds) std::printf(" %s %.3f", s.name.c_str(), s.seconds);
  std::printf("\n  voxelization %.3f s: %.3g M voxels/s, %.3g M triangles/s\n", r.voxelize_seconds,
              r.voxels_per_s / 1e6, r.triangles_per_s / 1e6);
  std::printf("  peak RSS %.1f MiB (this process); plain read of the mesh %.3g ms (%.2f GB/s): build = %.0fx the read\n",
              mib(r.peak_rss_bytes), 1e3 * r.read.seconds, r.read.gb_per_s(), r.read_ratio);
  if (!c) {
    std::printf("  %s\n", peer.status.c_str());
    return;
  }
  const bench::PeerCounts& n = c->counts_from == "ssvdag" ? c->peer.ssvdag : c->peer.svdag;
  std::printf("  peer voxcom: %.3f s (best of %zu), max RSS %.1f MiB; %llu voxels, %llu %s nodes (levels >= 2)\n",
              c->peer.wall_seconds, peer.runs.size(), mib(c->peer.max_rss_bytes), (unsigned long long)n.voxels,
              (unsigned long long)(b.format == "svo" ? n.svo_nodes : n.dag_nodes),
              b.format == "svo" ? "octree" : c->counts_from.c_str());
  std::printf("  megavox / peer: wall %.2f (build + device open), RSS %.2f; voxels %+.4f%%, nodes %+.4f%%\n",
              c->wall_ratio, c->rss_ratio, 100 * c->voxel_difference, 100 * c->node_difference);
}

nlohmann::json counts_json(const bench::PeerCounts& n) {
  return {{"voxels", n.voxels}, {"svo_nodes", n.svo_nodes}, {"dag_nodes", n.dag_nodes}};
}

nlohmann::json peer_json(const std::string& path, const PeerOutcome& peer, const bench::PeerComparison* c) {
  if (!c) return nullptr;
  nlohmann::json runs = nlohmann::json::array();
  for (const auto& run : peer.runs) runs.push_back(run.wall_seconds);
  return {{"name", "voxcom"},
          {"path", path},
          {"wall_seconds", c->peer.wall_seconds},
          {"wall_seconds_runs", runs},
          {"max_rss_bytes", c->peer.max_rss_bytes},
          {"svdag", counts_json(c->peer.svdag)},
          {"ssvdag", counts_json(c->peer.ssvdag)},
          {"counts_from", c->counts_from},
          {"wall_ratio", c->wall_ratio},
          {"rss_ratio", c->rss_ratio},
          {"voxel_difference", c->voxel_difference},
          {"node_difference", c->node_difference}};
}

nlohmann::json result_json(const bench::BuildBenchResult& r, const std::string& device, double open_seconds,
                           const BenchBuildArgs& a, const PeerOutcome& peer, const bench::PeerComparison* c) {
  nlohmann::json seconds = nlohmann::json::object();
  for (const auto& s : r.report.seconds) seconds[s.name] = s.seconds;
  return {{"benchmark", "build"},
          {"device", device},
          {"mesh", r.report.input},
          {"resolution", r.report.resolution},
          {"format", r.report.format},
          {"voxelize", r.report.voxelize},
          {"grid_origin", r.report.grid_origin},
          {"cube", r.report.cube},
          {"repeats", a.repeats},
          {"triangles", r.report.triangles},
          {"voxels", r.report.voxels},
          {"nodes_total", r.report.nodes_total},
          {"bytes", r.report.bytes},
          {"wall_seconds", r.best_seconds},
          {"wall_seconds_runs", r.wall_seconds},
          {"device_open_seconds", open_seconds},
          {"seconds", seconds},
          {"voxelize_seconds", r.voxelize_seconds},
          {"voxels_per_s", r.voxels_per_s},
          {"triangles_per_s", r.triangles_per_s},
          {"peak_rss_bytes", r.peak_rss_bytes},
          {"read_bytes", r.read.bytes},
          {"read_seconds", r.read.seconds},
          {"read_gb_per_s", r.read.gb_per_s()},
          {"read_ratio", r.read_ratio},
          {"build", report_json(r.report)},
          {"peer_status", peer.status},
          {"peer", peer_json(a.peer, peer, c)}};
}

}  // namespace

void add_bench_build_command(CLI::App& bench, const GlobalOptions& g) {
  auto a = std::make_shared<BenchBuildArgs>();
  auto* cmd = bench.add_subcommand(
      "build",
      "Time `megavox build` on a mesh with the same options (in core, or out of core by --cube; the global\n"
      "--device-memory applies as to build): wall time per run and per stage, voxelization voxels/s and\n"
      "triangles/s, this process's peak RSS, voxel and node counts, and the build against a plain read of the\n"
      "mesh file. With --voxelize thin --grid-origin min (voxcom's grid and rule), voxcom's voxelizer runs on the\n"
      "same input first (its wall time, max RSS and counts; megavox / peer ratios). Example:\n"
      "  megavox bench build bunny.ply --resolution 2K --voxelize thin --grid-origin min --format ssvdag");
  add_build_options(*cmd, *a);
  cmd->add_option("-o,--output", a->output, "Keep the .mvx built here (default: a scratch file, removed)");
  cmd->add_option("--repeats", a->repeats, "Builds (and peer runs); times are the best, memory the peak")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  cmd->add_option("--peer", a->peer, "voxcom's voxelizer (built by ../shared/peers/voxcom/build.sh)")
      ->capture_default_str();
  cmd->add_flag("--no-peer", a->no_peer, "Do not run the peer");
  cmd->add_option("--ranks", a->ranks,
                  "Also run the build under `mpirun -np 1` and `mpirun -np N` (this machine only: shared memory and\n"
                  "loopback), and report the speed-up of N ranks over one and whether the bytes are the same")
      ->check(CLI::Range(2, 256));
  cmd->add_flag("--json", a->json, "Print one JSON object instead of the table");
  cmd->callback([&g, a] {
    BuildOptions o = build_options(*a);
    o.output = a->output;
    // The read first warms the page cache for both programs. The peer runs before this process opens the
    // device and builds: some kernels start a child's ru_maxrss at the forked image's size.
    const bench::PlainRead read = bench::plain_read(o.input);
    const PeerOutcome peer = run_peer(*a, o);
    const auto t = bench::Clock::now();
    auto dev = open_device(g);
    const double open_seconds = bench::since(t);
    const bench::BuildBenchResult r = bench::run_build_bench(*dev, o, a->repeats, read);
    if (g.profile) print_kernel_totals(*dev);
    std::optional<bench::PeerComparison> c;
    if (!peer.runs.empty()) c = bench::compare_with_peer(r, peer.runs, open_seconds);
    const std::string device = dev->info().name;
    std::optional<RanksBench> ranks;
    if (a->ranks > 1) ranks = bench_ranks(with_verb({"build"}, build_argv(*a)), g, a->ranks, a->repeats);
    if (a->json) {
      nlohmann::json j = result_json(r, device, open_seconds, *a, peer, c ? &*c : nullptr);
      if (ranks) j["ranks"] = ranks_json(*ranks);
      std::cout << j.dump(2) << "\n";
    } else {
      print_table(r, device, open_seconds, peer, c ? &*c : nullptr);
      if (ranks) print_ranks_bench(*ranks);
    }
  });
}

}  // namespace mv::cli
