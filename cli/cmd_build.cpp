// `megavox build`: a mesh to a .mvx voxel DAG, with a summary table or one JSON object.
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>

#include "build_args.h"
#include "build_plan_text.h"
#include "cli_common.h"
#include "profile_report.h"
#include "megavox/build.h"
#include "megavox/error.h"
#include "megavox/ranks.h"
#include "rank_checks.h"

namespace mv::cli {

namespace {

struct BuildCommandArgs : BuildArgs {
  std::string output;
  bool json = false, quiet = false, no_clobber = false, resume = false;
};

// What makes a kept cube this build's: the options, the input's size and time, megavox's version.
uint64_t resume_fingerprint(const BuildCommandArgs& a) {
  std::string key = MEGAVOX_VERSION;
  for (const std::string& s : build_argv(a)) key += '\0' + s;
  std::error_code ec;
  key += '\0' + std::to_string(std::filesystem::file_size(a.input, ec));
  const auto time = std::filesystem::last_write_time(a.input, ec);
  key += '\0' + std::to_string(time.time_since_epoch().count());
  return std::hash<std::string>{}(key);
}

// A distributed build's ranks: what each made, read and exchanged, and the merge's share of the wall time.
nlohmann::json ranks_json(const BuildReport& r, const std::vector<dist::RankReport>& ranks) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& rr : ranks)
    list.push_back({{"seconds", rr.seconds}, {"voxels", rr.voxels}, {"cubes", rr.cubes}, {"voxel_estimate", rr.voxel_estimate},
                    {"bytes_read", rr.bytes_read}, {"bytes_exchanged", rr.bytes_exchanged},
                    {"peak_memory_bytes", rr.peak_memory_bytes}});
  double merge = 0;
  for (const auto& s : r.seconds)
    if (s.name.rfind("merge", 0) == 0) merge += s.seconds;
  return {{"ranks", list}, {"merge_share", ranks.empty() || ranks[0].seconds <= 0 ? 0 : merge / ranks[0].seconds}};
}

void print_ranks(const std::vector<dist::RankReport>& ranks) {
  for (size_t i = 0; i < ranks.size(); ++i)
    std::printf("  rank %zu: %llu cubes (about %llu voxels), %llu voxels, %s exchanged, %.2f s\n", i,
                (unsigned long long)ranks[i].cubes, (unsigned long long)ranks[i].voxel_estimate,
                (unsigned long long)ranks[i].voxels, format_bytes(ranks[i].bytes_exchanged).c_str(), ranks[i].seconds);
}

void print_table(const BuildReport& r) {
  std::string cubes = r.cube ? ", out of core in cubes of " + std::to_string(r.cube) + "^3" : "";
  if (r.cube_retries) cubes += " (halved " + std::to_string(r.cube_retries) + "x to fit device memory)";
  if (r.cubes_resumed) cubes += ", " + std::to_string(r.cubes_resumed) + " cubes kept by an earlier run";
  std::printf("%s -> %s (%s, %u^3%s)\n", r.input.c_str(), r.output.c_str(), r.format.c_str(), r.resolution,
              cubes.c_str());
  if (!r.vdb_grid.empty())
    std::printf("  grid '%s' (%s), voxels %llu\n", r.vdb_grid.c_str(), r.vdb_class.c_str(), (unsigned long long)r.voxels);
  else if (r.voxelize == "points")
    std::printf("  points %llu, voxels %llu (grid origin %s: %.9g,%.9g,%.9g, voxel %.9g)\n", (unsigned long long)r.points,
                (unsigned long long)r.voxels, r.grid_origin.c_str(), r.grid.origin[0], r.grid.origin[1],
                r.grid.origin[2], r.grid.voxel_size);
  else
    std::printf("  triangles %llu, voxels %llu (%s, grid origin %s: %.9g,%.9g,%.9g, voxel %.9g)\n",
                (unsigned long long)r.triangles, (unsigned long long)r.voxels, r.voxelize.c_str(), r.grid_origin.c_str(),
                r.grid.origin[0], r.grid.origin[1], r.grid.origin[2], r.grid.voxel_size);
  std::printf("  %-6s %14s %14s %8s\n", "level", "octree nodes", "DAG nodes", "DAG/SVO");
  for (size_t l = 0; l < r.nodes_per_level.size(); ++l)
    std::printf("  %-6zu %14llu %14llu %8.3f\n", l, (unsigned long long)r.svo_nodes[l],
                (unsigned long long)r.nodes_per_level[l],
                r.svo_nodes[l] ? double(r.nodes_per_level[l]) / double(r.svo_nodes[l]) : 0.0);
  std::printf("  DAG nodes (levels >= 2): %llu; encoded %llu bytes, %.3f bits per voxel\n",
              (unsigned long long)r.nodes_total, (unsigned long long)r.bytes, r.bits_per_voxel);
  if (r.colour_entries)
    std::printf("  colours (%s, %s RGB24): %llu entries (voxels and inner nodes), %llu bytes, %.3f bits per voxel; "
                "palette %llu bytes, selected in %.3f s\n",
                r.attributes.c_str(), r.colour_format.c_str(), (unsigned long long)r.colour_entries,
                (unsigned long long)r.colour_bytes, r.colour_bits_per_voxel,
                (unsigned long long)r.colour_palette_bytes, r.colour_palette_seconds);
  if (r.colour_quantize.bits < 24) {
    const ColourQuantizeReport& q = r.colour_quantize;
    std::printf("  quantized to %u bits: %llu -> %llu colours; error mean %.2f/%.2f/%.2f max %.0f/%.0f/%.0f (R/G/B), "
                "dE94 mean %.3f max %.3f\n", q.bits, (unsigned long long)q.colours_in,
                (unsigned long long)q.colours_out, q.mean_rgb[0], q.mean_rgb[1], q.mean_rgb[2], q.max_rgb[0],
                q.max_rgb[1], q.max_rgb[2], q.mean_delta_e, q.max_delta_e);
  }
  std::printf("  seconds:");
  for (const auto& s : r.seconds) std::printf(" %s %.3f", s.name.c_str(), s.seconds);
  std::printf("\n");
}

}  // namespace

void add_build_command(CLI::App& app, const GlobalOptions& g) {
  auto a = std::make_shared<BuildCommandArgs>();
  auto* cmd = app.add_subcommand(
      "build",
      "Voxelize a triangle mesh (PLY, binary or ASCII, streamed; OBJ, glTF, FBX, STL, ... through assimp) at a\n"
      "resolution, or read an OpenVDB volume (level sets: surface voxels; fog: voxels > 0), and reduce it to a\n"
      "voxel DAG in a .mvx file. The grid is a cube on the mesh's longest extent (--grid-origin, --bounds); voxel i\n"
      "covers [i, i+1) and the grid's top face belongs to the last voxel. Example:\n"
      "  megavox build bunny.ply --resolution 4K --format ssvdag -o bunny.mvx\n"
      "  megavox build bunny.ply --resolution 2K --voxelize thin --grid-origin min -o bunny_thin.mvx\n"
      "Over MPI ranks (a build in cubes; a binary PLY of triangles is read in shares of its faces; the same bytes):\n"
      "  mpirun -np 4 megavox build scan.ply --resolution 16K -o scan.mvx");
  add_build_options(*cmd, *a);
  cmd->add_option("-o,--output", a->output, "The .mvx file to write (named only once complete)")
      ->required();
  cmd->add_flag("--json", a->json, "Print one JSON object instead of the table");
  cmd->add_flag("-q,--quiet", a->quiet, "No progress bar");
  add_no_clobber_flag(*cmd, a->no_clobber);
  cmd->add_flag("--resume", a->resume,
                "Keep each finished cube in OUTPUT.cubes/ and reuse the cubes a run of this same build kept there\n"
                "(each checked): a build in cubes that failed or was stopped goes on where it was. The folder goes\n"
                "once the output is written");
  cmd->callback([&g, a] {
    BuildOptions o = build_options(*a);
    o.output = a->output;
    o.no_clobber = a->no_clobber;
    if (a->resume) {
      o.resume_dir = a->output + ".cubes";
      o.resume_fingerprint = resume_fingerprint(*a);
    }
    // Under mpirun: every rank takes part in an out-of-core build; rank 0 writes the output and reports.
    const dist::World& world = dist::world();
    const bool lead = world.rank == 0;
    std::optional<dist::CubeRanks> ranks;
    if (world.size > 1) {
      check_every_rank_reads(o.input);
      ranks.emplace(world);
      o.ranks = &ranks->build_ranks();
    }
    const auto start = std::chrono::steady_clock::now();
    if (lead) check_output(o);  // before the device opens
    auto dev = open_device(g, a->quiet || !lead);
    const bool bar = !a->quiet && lead && isatty(STDERR_FILENO);
    // The plan goes to stderr (stdout keeps the table or the one JSON object), on its own line below the bar.
    const PlanListener plan = [&](const BuildPlan& p) {
      if (bar) std::fprintf(stderr, "\r\033[2K");
      print_plan(p);
    };
    ParallelismMeter meter(*dev);
    if (g.profile) meter.start();
    BuildReport r = build_mvx(*dev, o, progress_bar(bar), a->quiet || !lead ? PlanListener{} : plan);
    if (bar) std::fprintf(stderr, "\n");
    std::vector<dist::RankReport> rank_reports;
    if (ranks) {
      ranks->finish();
      ranks->report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      ranks->report.voxels = lead ? 0 : r.voxels;  // rank 0's own: the total less the others' (below)
      std::error_code ec;
      // a share of the faces where the file allowed, else the whole input
      ranks->report.bytes_read = r.bytes_read ? r.bytes_read : std::filesystem::file_size(o.input, ec);
      ranks->report.bytes_exchanged += r.bytes_exchanged;
      rank_reports = dist::gather_reports(ranks->report);
      if (!lead) return;
      uint64_t others = 0;
      for (const auto& rr : rank_reports) others += rr.voxels;
      rank_reports[0].voxels = r.voxels - others;
    }
    nlohmann::json j = a->json ? report_json(r) : nlohmann::json();
    if (a->json && ranks) j.update(ranks_json(r, rank_reports));
    if (g.profile) {
      double io = 0;  // the stages that read the input and write the .mvx
      for (const auto& s : r.seconds)
        if (s.name == "read" || s.name == "write") io += s.seconds;
      const Parallelism p = meter.stop(io);
      if (a->json) j["parallelism"] = parallelism_json(p);
      else print_parallelism("build", p);
    }
    if (a->json) std::cout << j.dump(2) << "\n";
    else print_table(r);
    if (!a->json && ranks) print_ranks(rank_reports);
  });
}

}  // namespace mv::cli
