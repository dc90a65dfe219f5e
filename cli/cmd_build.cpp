// `megavox build`: a mesh to a .mvx voxel DAG, with a summary table or one JSON object.
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <cstdio>
#include <iostream>

#include "cli_common.h"
#include "megavox/build.h"
#include "megavox/error.h"

namespace mv::cli {

namespace {

struct BuildArgs {
  std::string input, output, resolution, format = "svdag", grid, grid_origin = "center", bounds, voxelize = "conservative";
  std::string memory;
  uint32_t cube = 1024;
  bool json = false, quiet = false;
};

// One line on stderr, redrawn in place; only on a terminal.
Progress progress_bar(bool enabled) {
  if (!enabled) return {};
  return [last = std::string()](const std::string& stage, double f) mutable {
    const int width = 30;
    int filled = static_cast<int>(f * width + 0.5);
    std::fprintf(stderr, "\r%-9s [%s%s] %3.0f%%", stage.c_str(), std::string(filled, '#').c_str(),
                 std::string(width - filled, ' ').c_str(), 100 * f);
    if (stage != last && !last.empty()) std::fprintf(stderr, "\n");
    last = stage;
    std::fflush(stderr);
  };
}

void print_table(const BuildReport& r) {
  std::string cubes = r.cube ? ", out of core in cubes of " + std::to_string(r.cube) + "^3" : "";
  if (r.cube_retries) cubes += " (halved " + std::to_string(r.cube_retries) + "x to fit device memory)";
  std::printf("%s -> %s (%s, %u^3%s)\n", r.input.c_str(), r.output.c_str(), r.format.c_str(), r.resolution,
              cubes.c_str());
  if (!r.vdb_grid.empty())
    std::printf("  grid '%s' (%s), voxels %llu\n", r.vdb_grid.c_str(), r.vdb_class.c_str(), (unsigned long long)r.voxels);
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
  std::printf("  seconds:");
  for (const auto& s : r.seconds) std::printf(" %s %.3f", s.name.c_str(), s.seconds);
  std::printf("\n");
}

}  // namespace

nlohmann::json report_json(const BuildReport& r) {
  nlohmann::json seconds = nlohmann::json::object();
  for (const auto& s : r.seconds) seconds[s.name] = s.seconds;
  return {{"input", r.input},         {"output", r.output},
          {"format", r.format},       {"resolution", r.resolution},
          {"triangles", r.triangles}, {"voxels", r.voxels},
          {"vdb_grid", r.vdb_grid},   {"vdb_class", r.vdb_class},   {"cube", r.cube},
          {"spilled_bytes", r.spilled_bytes}, {"vertex_scratch_bytes", r.vertex_scratch_bytes},
          {"cube_retries", r.cube_retries},
          {"voxelize", r.voxelize},   {"grid_origin", r.grid_origin},
          {"grid", {{"origin", r.grid.origin}, {"voxel_size", r.grid.voxel_size}}},
          {"svo_nodes_per_level", r.svo_nodes},
          {"nodes_per_level", r.nodes_per_level},
          {"nodes_total", r.nodes_total},
          {"bytes", r.bytes},         {"bits_per_voxel", r.bits_per_voxel},
          {"seconds", seconds}};
}

void add_build_command(CLI::App& app, const GlobalOptions& g) {
  auto a = std::make_shared<BuildArgs>();
  auto* cmd = app.add_subcommand(
      "build",
      "Voxelize a triangle mesh (PLY, binary or ASCII, streamed; OBJ, glTF, FBX, STL, ... through assimp) at a\n"
      "resolution, or read an OpenVDB volume (level sets: surface voxels; fog: voxels > 0), and reduce it to a\n"
      "voxel DAG in a .mvx file. The grid is a cube on the mesh's longest extent (--grid-origin, --bounds); voxel i\n"
      "covers [i, i+1) and the grid's top face belongs to the last voxel. Example:\n"
      "  megavox build bunny.ply --resolution 4K --format ssvdag -o bunny.mvx\n"
      "  megavox build bunny.ply --resolution 2K --voxelize thin --grid-origin min -o bunny_thin.mvx");
  cmd->add_option("input", a->input, "Mesh file (.ply, .obj, .gltf, .fbx, .stl, ...)")->required();
  cmd->add_option("-o,--output", a->output, "The .mvx file to write (written to OUT.tmp, renamed on success)")
      ->required();
  cmd->add_option("--resolution", a->resolution,
                  "Voxels per axis, a power of two: 1024, 2K, 16K, ... (default: 1K for meshes; for a .vdb the\n"
                  "smallest power of two that holds its voxels, one VDB voxel per voxel; a smaller one resamples)");
  cmd->add_option("--grid", a->grid, "The .vdb grid to read (default: the first)");
  cmd->add_option("--cube", a->cube,
                  "Meshes above this resolution build out of core, one cube of this many voxels per side at a time\n"
                  "(device memory holds one cube's voxels; a cube that does not fit --device-memory is retried at half\n"
                  "the size, down to 64); 0 = always in core")
      ->capture_default_str();
  cmd->add_option("--format", a->format,
                  "Encoding: svo (the plain octree, unreduced), svdag (the thesis / SymVox 32-bit layout),\n"
                  "ussvdag (symmetry-aware reduction, same layout with per-child mirror bits) or ssvdag\n"
                  "(symmetry-aware, compact 16-bit encoding)")
      ->check(CLI::IsMember({"svo", "svdag", "ussvdag", "ssvdag"}))
      ->capture_default_str();
  cmd->add_option("--grid-origin", a->grid_origin,
                  "Meshes: where the cube sits. center: centred on the bounds (SymVox); min: at the bounds' min corner,\n"
                  "shorter axes start at 0 (voxcom, cuda_voxelizer)")
      ->check(CLI::IsMember({"center", "min"}))
      ->capture_default_str();
  cmd->add_option("--bounds", a->bounds,
                  "Meshes: an explicit cube X,Y,Z,SIZE (min corner and side, in the mesh's units), so several inputs\n"
                  "share one grid; geometry outside it is cut away")
      ->excludes("--grid-origin");
  cmd->add_option("--voxelize", a->voxelize,
                  "Meshes: conservative (every voxel a triangle touches, exact; 26-separating) or thin (Schwarz &\n"
                  "Seidel's 6-separating surface, about 1/3 fewer voxels)")
      ->check(CLI::IsMember({"conservative", "thin"}))
      ->capture_default_str();
  cmd->add_option("--memory", a->memory,
                  "Host RAM budget (e.g. 8G, 512M; default: half the RAM). PLY vertex positions past a quarter of it,\n"
                  "and out of core the triangles past another quarter, go to scratch files in $TMPDIR (or /tmp); a\n"
                  "build that would still pass it stops with an error naming what it needs");
  cmd->add_flag("--json", a->json, "Print one JSON object instead of the table");
  cmd->add_flag("-q,--quiet", a->quiet, "No progress bar");
  cmd->callback([&g, a] {
    BuildOptions o;
    o.input = a->input;
    o.output = a->output;
    o.resolution = a->resolution.empty() ? 0 : parse_resolution(a->resolution);
    o.grid = a->grid;
    o.cube = a->cube;
    o.format = a->format;
    o.placement = a->bounds.empty() ? parse_grid_origin(a->grid_origin) : parse_grid_bounds(a->bounds);
    o.voxelize = a->voxelize;
    o.memory = a->memory.empty() ? 0 : parse_size(a->memory);
    auto dev = open_device(g);
    BuildReport r = build_mvx(*dev, o, progress_bar(!a->quiet && isatty(STDERR_FILENO)));
    if (!a->quiet && isatty(STDERR_FILENO)) std::fprintf(stderr, "\n");
    if (g.profile) print_kernel_totals(*dev);
    if (a->json) std::cout << report_json(r).dump(2) << "\n";
    else print_table(r);
  });
}

}  // namespace mv::cli
