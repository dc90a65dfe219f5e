#include "build_args.h"

#include "build_plan_text.h"
#include "megavox/error.h"
#include "option_words.h"

namespace mv::cli {

std::vector<std::string> build_argv(const BuildArgs& a) {
  std::vector<std::string> v = {a.input, "--cube", std::to_string(a.cube), "--format", a.format, "--grid-origin",
                                a.grid_origin, "--voxelize", a.voxelize, "--attributes", a.attributes,
                                "--colour-bits", std::to_string(a.colour_bits), "--page-order", a.page_order,
                                "--page-words", std::to_string(a.page_words)};
  for (const auto& [flag, value] : {std::pair<const char*, const std::string*>{"--resolution", &a.resolution},
                                    {"--grid", &a.grid}, {"--bounds", &a.bounds}, {"--memory", &a.memory}})
    if (!value->empty()) v.insert(v.end(), {flag, *value});
  return v;
}

void add_build_options(CLI::App& cmd, BuildArgs& a) {
  cmd.add_option("input", a.input,
                 "Mesh file (.ply, .obj, .gltf, .fbx, .stl, ...), or a point cloud (.las, or a .ply with vertices and\n"
                 "no faces): each point fills the voxel it falls in")
      ->required();
  cmd.add_option("--resolution", a.resolution,
                 "Voxels per axis, a power of two: 1024, 2K, 16K, ... (default: 1K for meshes; for a .vdb the\n"
                 "smallest power of two that holds its voxels, one VDB voxel per voxel; a smaller one resamples)");
  cmd.add_option("--grid", a.grid, "The .vdb grid to read (default: the first)");
  cmd.add_option("--cube", a.cube,
                 "Meshes above this resolution build out of core, one cube of this many voxels per side at a time\n"
                 "(device memory holds one cube's voxels; a cube that does not fit --device-memory is retried at half\n"
                 "the size, down to 64); 0 = always in core")
      ->capture_default_str();
  cmd.add_option("--format", a.format,
                 "Encoding: svo (the plain octree, unreduced), svdag (the thesis / SymVox 32-bit layout),\n"
                 "ussvdag (symmetry-aware reduction, same layout with per-child mirror bits) or ssvdag\n"
                 "(symmetry-aware, compact 16-bit encoding)")
      ->check(CLI::IsMember({"svo", "svdag", "ussvdag", "ssvdag"}))
      ->capture_default_str();
  cmd.add_option("--grid-origin", a.grid_origin,
                 "Meshes: where the cube sits. center: centred on the bounds (SymVox); min: at the bounds' min corner,\n"
                 "shorter axes start at 0 (voxcom, cuda_voxelizer)")
      ->check(CLI::IsMember({"center", "min"}))
      ->capture_default_str();
  cmd.add_option("--bounds", a.bounds,
                 "Meshes: an explicit cube X,Y,Z,SIZE (min corner and side, in the mesh's units), so several inputs\n"
                 "share one grid; geometry outside it is cut away")
      ->excludes("--grid-origin");
  cmd.add_option("--voxelize", a.voxelize,
                 "Meshes: conservative (every voxel a triangle touches, exact; 26-separating) or thin (Schwarz &\n"
                 "Seidel's 6-separating surface, about 1/3 fewer voxels)")
      ->check(CLI::IsMember({"conservative", "thin"}))
      ->capture_default_str();
  cmd.add_option("--attributes", a.attributes,
                 "Voxel colours, stored in depth-first order beside the DAG. rgb: a cloud's voxel takes the mean of its\n"
                 "points; a mesh's voxel the colour at the point nearest its centre on the triangles overlapping it\n"
                 "(vertex colours interpolated, or a base-colour texture sampled bilinearly; PLY red, green, blue as\n"
                 "uchar or ushort, or what assimp reads; meshes build colours in core); inner nodes the mean of the\n"
                 "voxels below. none: geometry only; auto: rgb when the input has colour")
      ->check(CLI::IsMember({"auto", "none", "rgb"}))
      ->capture_default_str();
  cmd.add_option("--colour-bits", a.colour_bits,
                 "Colours: 24 keeps them; 16, 14 or 12 quantize them to at most 2^bits colours (k-means in\n"
                 "CIELAB, deterministic) before palette compression, and report the errors (RGB, ΔE CIE94)")
      ->check(CLI::IsMember({24u, 16u, 14u, 12u}))
      ->capture_default_str();
  cmd.add_option("--memory", a.memory,
                 "Host RAM budget (e.g. 8G, 512M; default: half the RAM). PLY vertex positions past a quarter of it,\n"
                 "and out of core the triangles past another quarter, go to scratch files in $TMPDIR (or /tmp); a\n"
                 "build that would still pass it stops with an error naming what it needs");
  cmd.add_option("--page-order", a.page_order,
                 "How svo / svdag / ussvdag nodes share the file's 16 KiB pages (what a render through the page cache\n"
                 "reads). subtree: each page around a subtree, so a descent reads about half the pages (pointers\n"
                 "absolute: up to 2^32 words, 16 GiB, past which the writer takes level order); level: the levels one\n"
                 "after another, pointers counting from their level's start (any size). An ssvdag is always in level order")
      ->check(CLI::IsMember({"subtree", "level"}))
      ->capture_default_str();
  cmd.add_option("--page-words", a.page_words,
                 "32-bit words a page of the file holds, what a page cache loads at once: a power of two from 16 to\n"
                 "2^24 (default 16 KiB pages; smaller pages let a smaller cache stream the file, at more passes)")
      ->check(CLI::Range(16u, 1u << 24))
      ->capture_default_str();
}

BuildOptions build_options(const BuildArgs& a) {
  BuildOptions o;
  o.input = a.input;
  o.resolution = a.resolution.empty() ? 0 : parse_resolution(a.resolution);
  o.grid = a.grid;
  o.cube = a.cube;
  o.encoding = parse_encoding(a.format);
  o.placement = a.bounds.empty() ? parse_grid_origin(a.grid_origin) : parse_grid_bounds(a.bounds);
  o.voxelize = parse_voxelize_rule(a.voxelize);
  o.memory = a.memory.empty() ? 0 : parse_size(a.memory);
  o.colour_bits = a.colour_bits;
  o.paging.order = a.page_order == "level" ? NodeOrder::level : NodeOrder::subtree;
  if (a.page_words & (a.page_words - 1))
    throw Error("--page-words " + std::to_string(a.page_words) + ": a power of two from 16 to 2^24 is needed");
  o.paging.page_words = a.page_words;
  o.attributes = a.attributes == "rgb" ? Attributes::rgb : a.attributes == "none" ? Attributes::none : Attributes::automatic;
  return o;
}

nlohmann::json report_json(const BuildReport& r) {
  nlohmann::json seconds = nlohmann::json::object();
  for (const auto& s : r.seconds) seconds[s.name] = s.seconds;
  return {{"input", r.input},         {"output", r.output},
          {"format", r.format},       {"resolution", r.resolution},
          {"triangles", r.triangles}, {"voxels", r.voxels},
          {"points", r.points},       {"attributes", r.attributes},
          {"colour_entries", r.colour_entries}, {"colour_bytes", r.colour_bytes},
          {"colour_bits", r.colour_entries ? r.colour_quantize.bits : 0},
          {"colour_quantize", {{"colours_in", r.colour_quantize.colours_in}, {"colours_out", r.colour_quantize.colours_out},
                               {"mean_rgb_error", r.colour_quantize.mean_rgb}, {"max_rgb_error", r.colour_quantize.max_rgb},
                               {"mean_delta_e94", r.colour_quantize.mean_delta_e}, {"max_delta_e94", r.colour_quantize.max_delta_e},
                               {"iterations", r.colour_quantize.iterations}, {"seconds", r.colour_quantize.seconds}}}, {"colour_bits_per_voxel", r.colour_bits_per_voxel},
          {"colour_format", r.colour_format}, {"colour_palette_bytes", r.colour_palette_bytes},
          {"colour_palette_seconds", r.colour_palette_seconds},
          {"vdb_grid", r.vdb_grid},   {"vdb_class", r.vdb_class},   {"cube", r.cube}, {"cubes_resumed", r.cubes_resumed},
          {"spilled_bytes", r.spilled_bytes}, {"vertex_scratch_bytes", r.vertex_scratch_bytes},
          {"cube_retries", r.cube_retries},
          {"voxelize", r.voxelize},   {"grid_origin", r.grid_origin},
          {"grid", {{"origin", r.grid.origin}, {"voxel_size", r.grid.voxel_size}}},
          {"svo_nodes_per_level", r.svo_nodes},
          {"nodes_per_level", r.nodes_per_level},
          {"nodes_total", r.nodes_total},
          {"bytes", r.bytes},         {"bits_per_voxel", r.bits_per_voxel},
          {"seconds", seconds},       {"plan", plan_json(r.plan)}};
}

}  // namespace mv::cli
