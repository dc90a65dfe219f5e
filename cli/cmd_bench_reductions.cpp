// `megavox bench reductions`: one voxelized mesh reduced to an SVDAG and to an SSVDAG from the same octree.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

#include "reduction_bench.h"
#include "cli_common.h"
#include "megavox/build.h"

namespace mv::cli {

void add_bench_reductions_command(CLI::App& bench, const GlobalOptions& g) {
  struct Args {
    std::string mesh, resolution = "2K";
    int repeats = 5;
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = bench.add_subcommand(
      "reductions",
      "Voxelize a PLY mesh once, then reduce the same octree to an SVDAG and to an SSVDAG: seconds per stage,\n"
      "voxels/s (filled voxels / reduction time), node counts, and the SSVDAG/SVDAG time and byte ratios\n"
      "(bytes: ssvdag vs svdag, as the thesis compares them; also ussvdag vs svdag). A plain read of the mesh\n"
      "file is the baseline floor.");
  cmd->add_option("mesh", a->mesh, "Mesh file (.ply)")->required();
  cmd->add_option("--resolution", a->resolution, "Voxels per axis, a power of two")->capture_default_str();
  cmd->add_option("--repeats", a->repeats, "Alternating SVDAG/SSVDAG reductions; times are the best, the ratio also "
                                          "the median of the pairs")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_flag("--json", a->json, "Print one JSON object");
  cmd->callback([&g, a] {
    auto dev = open_device(g);
    bench::ReductionBenchResult r = bench::run_reduction_bench(*dev, a->mesh, parse_resolution(a->resolution), a->repeats);
    if (g.profile) print_kernel_totals(*dev);
    if (a->json) {
      nlohmann::json j = {{"benchmark", "reductions"}, {"device", dev->info().name}, {"mesh", r.mesh},
                          {"resolution", r.resolution}, {"triangles", r.triangles}, {"voxels", r.voxels},
                          {"voxelize_seconds", r.voxelize_seconds}, {"svo_seconds", r.svo_seconds},
                          {"svdag_seconds", r.svdag_seconds}, {"ssvdag_seconds", r.ssvdag_seconds},
                          {"svdag_voxels_per_s", r.svdag_voxels_per_s}, {"ssvdag_voxels_per_s", r.ssvdag_voxels_per_s},
                          {"svdag_nodes", r.svdag_nodes}, {"ssvdag_nodes", r.ssvdag_nodes},
                          {"svdag_bytes", r.svdag_bytes}, {"ussvdag_bytes", r.ussvdag_bytes},
                          {"ssvdag_bytes", r.ssvdag_bytes}, {"time_ratio", r.time_ratio},
                          {"time_ratio_median", r.time_ratio_median}, {"repeats", a->repeats},
                          {"byte_ratio", r.compact_byte_ratio}, {"ussvdag_byte_ratio", r.byte_ratio},
                          {"read_gb_per_s", r.read_gb_per_s}};
      std::cout << j.dump(2) << "\n";
      return;
    }
    std::printf("%s at %u^3 on %s: %llu triangles, %llu voxels\n", r.mesh.c_str(), r.resolution,
                dev->info().name.c_str(), (unsigned long long)r.triangles, (unsigned long long)r.voxels);
    std::printf("  voxelize %.3f s; octree %.3f s; SVDAG %.3f s (%.1f M voxels/s); SSVDAG %.3f s (%.1f M voxels/s)\n",
                r.voxelize_seconds, r.svo_seconds, r.svdag_seconds, r.svdag_voxels_per_s / 1e6, r.ssvdag_seconds,
                r.ssvdag_voxels_per_s / 1e6);
    std::printf("  nodes (levels >= 2): SVDAG %llu, SSVDAG %llu; bytes: svdag %llu, ussvdag %llu, ssvdag %llu\n",
                (unsigned long long)r.svdag_nodes, (unsigned long long)r.ssvdag_nodes,
                (unsigned long long)r.svdag_bytes, (unsigned long long)r.ussvdag_bytes,
                (unsigned long long)r.ssvdag_bytes);
    std::printf("  SSVDAG/SVDAG: time %.2f (median of %d pairs %.2f), bytes %.3f (ssvdag/svdag; ussvdag/svdag %.3f); plain read of the mesh "
                "%.2f GB/s\n",
                r.time_ratio, a->repeats, r.time_ratio_median, r.compact_byte_ratio, r.byte_ratio, r.read_gb_per_s);
  });
}

}  // namespace mv::cli
