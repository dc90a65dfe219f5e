// `megavox points build | info | render` (and convert, cmd_points_convert.cpp): point clouds to LOD hierarchies (.mvx or 3D Tiles), and what a file holds.
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <optional>
#include <cstdio>
#include <iostream>

#include "camera_options.h"
#include "cli_common.h"
#include "profile_report.h"
#include "io/output_path.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "megavox/point_build.h"
#include "megavox/point_render.h"
#include "megavox/render.h"
#include "option_words.h"
#include "megavox/ranks.h"
#include "rank_checks.h"

namespace mv::cli {

namespace {

struct PointsBuildArgs {
  std::string input, output, format = "mvx", memory, bounds, tiles_version = "1.1", crs;
  uint32_t depth = 0, max_node_points = 16384, sort_ranges = PointBuildOptions().sort_ranges;
  bool skip_extra = false, json = false, quiet = false, no_clobber = false;
};

nlohmann::json report_json(const PointFileReport& r) {
  return {{"input", r.input},
          {"output", r.output},
          {"format", r.format},
          {"input_format", r.input_format},
          {"points_in", r.points_in},
          {"points_kept", r.points_kept},
          {"points_dropped", r.points_dropped},
          {"stored_points", r.stored_points},
          {"nodes", r.nodes},
          {"nodes_per_level", r.nodes_per_level},
          {"depth", r.depth},
          {"seconds",
           {{"read", r.read_seconds}, {"sort", r.sort_seconds}, {"build", r.build_seconds}, {"write", r.write_seconds},
            {"total", r.total_seconds}}},
          {"points_per_second", r.points_per_second},
          {"sort_runs", r.sort_runs},
          {"out_of_core", r.out_of_core}};
}

// A build over ranks: what each rank read, built and exchanged, and the join's share of rank 0's wall time.
nlohmann::json point_ranks_json(const PointFileReport& r, const std::vector<dist::RankReport>& ranks) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& rr : ranks)
    list.push_back({{"seconds", rr.seconds}, {"points", rr.points}, {"points_read", rr.points_read}, {"tiles", rr.tiles},
                    {"bytes_read", rr.bytes_read}, {"bytes_exchanged", rr.bytes_exchanged},
                    {"peak_memory_bytes", rr.peak_memory_bytes}});
  const double wall = ranks.empty() ? 0 : ranks[0].seconds;
  return {{"ranks", list}, {"merge_share", wall > 0 ? r.ranks.join_seconds / wall : 0}};
}

void print_point_ranks(const std::vector<dist::RankReport>& ranks) {
  for (size_t i = 0; i < ranks.size(); ++i)
    std::printf("  rank %zu: read %llu points, built %llu, %s exchanged, %.2f s\n", i,
                (unsigned long long)ranks[i].points_read, (unsigned long long)ranks[i].points,
                format_bytes(ranks[i].bytes_exchanged).c_str(), ranks[i].seconds);
}

void print_levels(const std::vector<uint64_t>& per_level) {
  std::printf("  %-6s %12s\n", "level", "nodes");
  for (size_t l = 0; l < per_level.size(); ++l) std::printf("  %-6zu %12llu\n", l, (unsigned long long)per_level[l]);
}

void print_report(const PointFileReport& r) {
  std::printf("%s -> %s (%s; input %s)\n", r.input.c_str(), r.output.c_str(), r.format.c_str(), r.input_format.c_str());
  std::printf("  points in %llu, kept %llu, dropped %llu; %llu nodes over %u levels, %llu points stored (leaves + "
              "representatives)\n",
              (unsigned long long)r.points_in, (unsigned long long)r.points_kept, (unsigned long long)r.points_dropped,
              (unsigned long long)r.nodes, r.depth + 1, (unsigned long long)r.stored_points);
  if (r.out_of_core)
    std::printf("  sorted out of core: %llu runs on disk, merged while building (the cloud is over --memory)\n",
                (unsigned long long)r.sort_runs);
  print_levels(r.nodes_per_level);
  std::printf("  seconds: read %.3f (alone), sort %.3f, build %.3f, write %.3f; total %.3f = %.2f M points/s\n",
              r.read_seconds, r.sort_seconds, r.build_seconds, r.write_seconds, r.total_seconds,
              r.points_per_second * 1e-6);
}

void add_points_build(CLI::App& points, const GlobalOptions& g) {
  auto a = std::make_shared<PointsBuildArgs>();
  auto* cmd = points.add_subcommand(
      "build",
      "Build an LOD hierarchy of a point cloud (PLY binary or ASCII: x,y,z with optional colour, normals and\n"
      "intensity; LAS 1.0-1.4 point formats 0-10, LAZ 0-3 and 6-8) bottom-up from its Morton order (OMiCroN).\n"
      "Every point lands in exactly one leaf; a subtree of at most --max-node-points points is one leaf, and each inner node\n"
      "keeps copies of its children's points, one per cell of a 64^3 grid over its cube, nearest the cell centre.\n"
      "Examples:\n"
      "  megavox points build scan.las -o scan.mvx\n"
      "  megavox points build scan.las --format 3dtiles -o scan_tiles   (DIR/tileset.json + DIR/tiles/*.glb)\n"
      "Over MPI ranks (each reads a slice, builds its cells' subtrees and writes their tiles; the same bytes):\n"
      "  mpirun -np 4 megavox points build scan.laz -o scan.mvx");
  cmd->add_option("input", a->input, "The point cloud (.ply, .las)")->required();
  cmd->add_option("-o,--output", a->output, "The .mvx file or, with --format 3dtiles, the folder to write "
                                            "(written under a temporary name, renamed on success)")
      ->required();
  cmd->add_option("--format", a->format, "mvx (default) or 3dtiles");
  cmd->add_option("--tiles-version", a->tiles_version,
                  "3dtiles: 1.1 (default: glTF tiles, placed on the globe when the cloud has a CRS) or 1.0 (.pnts "
                  "tiles in the input's coordinates)");
  cmd->add_option("--crs", a->crs,
                  "3dtiles: the CRS to place the tileset with (EPSG:N or WKT), over the one the input declares");
  cmd->add_option("--depth", a->depth, "Leaf level, 1-21 (default: from the point count, see docs/ARCHITECTURE.md)");
  cmd->add_option("--max-node-points", a->max_node_points,
                  "Most points in a leaf subtree and representatives per inner node (default 16384)");
  cmd->add_option("--memory", a->memory, "Host memory budget, e.g. 8G (default: half the machine's RAM)");
  cmd->add_option("--sort-ranges", a->sort_ranges,
                  "Parts of the in-memory sort the builder takes while the rest sorts (1: after the whole sort)")
      ->capture_default_str();
  cmd->add_flag("--skip-attributes,--skip-extra-bytes", a->skip_extra,
                "Do not carry a LAS file's attribute record (classification, returns, GPS time, ..., extra bytes)");
  cmd->add_option("--bounds", a->bounds,
                  "LAS and LAZ: only the points in MINX,MINY,MINZ,MAXX,MAXY,MAXZ (world units); a COPC file "
                  "decodes only the chunks whose octree node meets the box");
  cmd->add_flag("--json", a->json, "Print one JSON object instead of the summary");
  cmd->add_flag("-q,--quiet", a->quiet, "No progress bar");
  add_no_clobber_flag(*cmd, a->no_clobber);
  cmd->callback([&g, a] {
    PointFileOptions o;
    o.no_clobber = a->no_clobber;
    o.input = a->input;
    o.output = a->output;
    o.format = parse_point_output(a->format);
    if (a->tiles_version != "1.1" && a->tiles_version != "1.0")
      throw CodedError(ErrorCode::invalid_argument, "--tiles-version '" + a->tiles_version + "': choose 1.1 or 1.0");
    const bool tiles_option = a->tiles_version != "1.1" || !a->crs.empty();
    if (tiles_option && o.format != PointOutput::tiles3d)
      throw CodedError(ErrorCode::invalid_argument, "--tiles-version and --crs apply to --format 3dtiles only",
                       setting_encoding);
    o.tiles_minor_version = a->tiles_version == "1.0" ? 0 : 1;
    o.crs = a->crs;
    o.build.depth = a->depth;
    o.build.max_node_points = a->max_node_points;
    o.build.sort_ranges = std::max(1u, a->sort_ranges);
    o.memory = a->memory.empty() ? 0 : parse_size(a->memory);
    o.carry_extra_bytes = !a->skip_extra;
    if (!a->bounds.empty()) o.bounds = parse_bounds(a->bounds);
    // Under mpirun: every rank builds a share; rank 0 writes the output and reports.
    const dist::World& world = dist::world();
    const bool lead = world.rank == 0;
    std::optional<RankCollectives> ranks;
    if (world.size > 1) {
      check_every_rank_reads(o.input);
      ranks = dist::collectives(world);
      o.ranks = &*ranks;
    }
    const auto start = std::chrono::steady_clock::now();
    if (lead) check_output(o);  // before the device opens
    auto dev = open_device(g, a->quiet || !lead);
    const bool bar = !a->quiet && lead && isatty(STDERR_FILENO);
    ParallelismMeter meter(*dev);
    if (g.profile) meter.start();
    PointFileReport r = build_points_file(*dev, o, progress_bar(bar));
    if (bar) std::fprintf(stderr, "\n");
    std::vector<dist::RankReport> rank_reports;
    if (ranks) {
      dist::RankReport mine;
      mine.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      mine.points = r.ranks.points_built;
      mine.points_read = r.ranks.points_read;
      mine.tiles = r.ranks.tiles_written;
      mine.bytes_read = r.ranks.bytes_read;
      mine.bytes_exchanged = r.ranks.bytes_exchanged;
      rank_reports = dist::gather_reports(mine);
      if (!lead) return;
    }
    nlohmann::json j = a->json ? report_json(r) : nlohmann::json();
    if (a->json && ranks) j.update(point_ranks_json(r, rank_reports));
    if (g.profile) {
      const Parallelism p = meter.stop(r.read_seconds + r.write_seconds);
      if (a->json) j["parallelism"] = parallelism_json(p);
      else print_parallelism("points build", p);
    }
    if (a->json) std::cout << j.dump(2) << "\n";
    else print_report(r);
    if (!a->json && ranks) print_point_ranks(rank_reports);
  });
}

void add_points_info(CLI::App& points) {
  auto path = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  auto* cmd = points.add_subcommand("info", "Validate a point .mvx file (checksums, the hierarchy's structure) and "
                                            "print its counts");
  cmd->add_option("file", *path, "The .mvx file")->required();
  cmd->add_flag("--json", *json, "Print one JSON object");
  cmd->callback([path, json] {
    PointHierarchy h = read_mvx_points(*path);
    if (*json) {
      nlohmann::json j = {{"file", *path},
                          {"input_format", h.source.format},
                          {"points_in", h.points_in},
                          {"points_kept", h.points_kept},
                          {"points_dropped", h.points_dropped},
                          {"stored_points", h.points.size()},
                          {"nodes", h.nodes.size()},
                          {"nodes_per_level", h.nodes_per_level},
                          {"depth", h.depth},
                          {"attributes", h.source.attributes},
                          {"z_up", h.source.z_up},
                          {"crs", h.source.crs}};
      std::cout << j.dump(2) << "\n";
      return;
    }
    std::printf("%s: point hierarchy, %llu points (in %llu, dropped %llu), %zu nodes, depth %u, valid\n",
                path->c_str(), (unsigned long long)h.points_kept, (unsigned long long)h.points_in,
                (unsigned long long)h.points_dropped, h.nodes.size(), h.depth);
    std::printf("  from %s; %s up%s%s\n", h.source.format.c_str(), h.source.z_up ? "+Z" : "+Y",
                h.source.crs.empty() ? "" : "; CRS ", h.source.crs.substr(0, 60).c_str());
    print_levels(h.nodes_per_level);
  });
}

struct PointsRenderArgs {
  std::string input, output;
  CameraArgs camera;
  PointRenderOptions render;
  bool during_build = false, no_clobber = false;
  uint32_t frames = 8, max_node_points = 16384, depth = 0;
};

void add_points_render(CLI::App& points, const GlobalOptions& g) {
  auto a = std::make_shared<PointsRenderArgs>();
  auto* cmd = points.add_subcommand(
      "render",
      "Render a point .mvx to a PNG: the LOD cut whose points' spacing projects to at most --lod-pixels, drawn as\n"
      "depth-tested square splats with eye-dome lighting (colour from RGB, else intensity, else height). The camera\n"
      "frames the cloud with +Z up for LAS input and +Y up for PLY (--up overrides), or stands at --eye in the\n"
      "cloud's own units. Examples:\n"
      "  megavox points render scan.mvx -o scan.png --view front --up z\n"
      "  megavox points render scan.mvx -o close.png --eye 10,20,5 --target 0,0,2 --up 0,0,1 --fov 30\n"
      "With --during-build the input is a cloud (PLY, LAS): it is built, and --frames pictures of OMiCroN's rendering\n"
      "front (the nodes drawn, kept and updated as the hierarchy grows; one camera) go to the folder -o, a line per\n"
      "frame (--json: a JSON line). There the front draws every formed point unless --lod-pixels is given, which coarsens it as a\n"
      "render's cut (front_nodes and points_drawn may then shrink as sibling groups prune into their parent):\n"
      "  megavox points render scan.las --during-build --frames 10 -o frames/");
  cmd->add_option("input", a->input, "The point .mvx file (--during-build: the point cloud)")->required();
  cmd->add_option("-o,--output", a->output,
                  "The picture to write: PNG, or JPEG for a .jpg/.jpeg name (--during-build: the folder)")
      ->required();
  add_no_clobber_flag(*cmd, a->no_clobber);
  cmd->add_flag("--during-build", a->during_build, "Build the input cloud and render frames while it grows");
  cmd->add_option("--frames", a->frames, "--during-build: how many frames")->capture_default_str();
  cmd->add_option("--max-node-points", a->max_node_points, "--during-build: as in points build")->capture_default_str();
  cmd->add_option("--depth", a->depth, "--during-build: as in points build (default: from the point count)");
  add_camera_options(*cmd, a->camera, "the file's: +Z for LAS input, +Y for PLY",
                     "Print one JSON object instead of the summary (--during-build prints a JSON line per frame)");
  cmd->add_option("--lod-pixels", a->render.lod_pixels,
                  "Largest projected point spacing of a drawn node (default 1; --during-build: 0, every point)");
  cmd->add_option("--point-size", a->render.point_size, "Splat side in pixels")->capture_default_str();
  cmd->callback([&g, a, cmd] {
    const CameraVectors v = camera_vectors(a->camera);
    a->render.width = a->camera.width;
    a->render.height = a->camera.height;
    a->render.view = a->camera.view;
    a->render.fov = a->camera.fov;
    a->render.eye = v.eye;
    a->render.target = v.target;
    a->render.up = v.up;
    const std::string output = io::resolve_output(
        {a->output, a->during_build ? io::OutputKind::kFolder : io::OutputKind::kFile,
         a->during_build ? "" : image_format(a->output), {a->input},
         uint64_t{a->render.width} * a->render.height * (a->during_build ? a->frames : 1), a->no_clobber});
    auto dev = open_device(g);
    if (a->during_build) {
      if (cmd->count("--lod-pixels") == 0) a->render.lod_pixels = 0;
      PointBuildOptions b;
      b.max_node_points = a->max_node_points;
      b.depth = a->depth;
      render_during_build(*dev, a->input, output, a->frames, b, a->render, [a](const BuildFrame& f) {
        if (a->camera.quiet) return;
        if (!a->camera.json) {
          std::printf("frame %u: %llu nodes, %llu drawn, %llu points -> %s\n", f.frame, (unsigned long long)f.nodes,
                      (unsigned long long)f.front_nodes, (unsigned long long)f.points_drawn, f.path.c_str());
          std::fflush(stdout);
          return;
        }
        nlohmann::json j = {{"frame", f.frame}, {"nodes", f.nodes}, {"front_nodes", f.front_nodes},
                          {"points_drawn", f.points_drawn}, {"file", f.path}};
        std::cout << j.dump() << std::endl;
      });
      return;
    }
    PointHierarchy h = read_mvx_points(a->input);
    PointRenderResult r = render_points(*dev, h, a->render);
    write_image(output, r.image);
    if (a->camera.quiet) return;
    if (a->camera.json) {
      nlohmann::json j = {{"file", a->input}, {"output", output}, {"width", r.image.width},
                          {"height", r.image.height}, {"nodes_drawn", r.nodes_drawn},
                          {"points_drawn", r.points_drawn}, {"pixels_covered", r.pixels_covered}};
      std::cout << j.dump(2) << "\n";
      return;
    }
    std::printf("%s -> %s (%ux%u): %llu nodes, %llu points drawn, %llu pixels covered\n", a->input.c_str(),
                a->output.c_str(), r.image.width, r.image.height, (unsigned long long)r.nodes_drawn,
                (unsigned long long)r.points_drawn, (unsigned long long)r.pixels_covered);
  });
}

}  // namespace

void add_points_command(CLI::App& app, const GlobalOptions& g) {
  CLI::App* points = app.add_subcommand("points", "Point clouds: LOD hierarchies (OMiCroN) in .mvx or 3D Tiles");
  points->require_subcommand(1);
  add_points_build(*points, g);
  add_points_info(*points);
  add_points_render(*points, g);
  add_points_convert(*points);
}

}  // namespace mv::cli
