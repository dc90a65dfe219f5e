// `megavox info`: what a .mvx file holds, after validating all of it.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

#include "paging/page_layout.h"
#include "cli_common.h"
#include "megavox/mvx.h"

namespace mv::cli {

void add_info_command(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  auto json = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand("info", "Validate a .mvx file (checksums, every page, structure) and print its header, "
                                          "counts and paging");
  cmd->add_option("file", *path, "The .mvx file")->required();
  cmd->add_flag("--json", *json, "Print one JSON object");
  cmd->callback([path, json] {
    MvxFile f = read_mvx(*path);
    uint64_t total = 0;
    for (size_t l = 2; l < f.dag_nodes.size(); ++l) total += f.dag_nodes[l];
    const uint64_t bytes = f.dag.bytes();
    const double bpv = f.voxels ? 8.0 * double(bytes) / double(f.voxels) : 0;
    const uint32_t pw = f.paging.page_words;
    const uint64_t pages = pw ? (f.paged_words + pw - 1) / pw : 0;
    // Colours: the section's bits (head included, inner nodes' colours included) over the voxels.
    const MvxColourStats& cs = f.colour_stats;
    const uint64_t colour_entries = f.colours.size() / 3, colour_bytes = cs.bytes;
    const double colour_bpv = f.voxels ? 8.0 * double(colour_bytes) / double(f.voxels) : 0;
    // The thesis's compression rate: the stored colours over the raw attribute array (3 bytes per entry).
    const double colour_rate = colour_entries ? double(colour_bytes) / (3.0 * double(colour_entries)) : 0;
    if (*json) {
      nlohmann::json j = {{"file", *path},
                          {"format", encoding_name(f.dag.encoding)},
                          {"levels", f.dag.levels},
                          {"resolution", f.grid.resolution},
                          {"origin", {f.grid.origin[0], f.grid.origin[1], f.grid.origin[2]}},
                          {"voxel_size", f.grid.voxel_size},
                          {"bounds", {{f.bounds.lo[0], f.bounds.lo[1], f.bounds.lo[2]}, {f.bounds.hi[0], f.bounds.hi[1], f.bounds.hi[2]}}},
                          {"voxels", f.voxels},
                          {"svo_nodes_per_level", f.svo_nodes},
                          {"nodes_per_level", f.dag_nodes},
                          {"nodes_total", total},
                          {"bytes", bytes},
                          {"bits_per_voxel", bpv},
                          {"colour_entries", colour_entries},
                          {"colour_bits", colour_entries ? f.colour_bits : 0},
                          {"colour_bytes", colour_bytes},
                          {"colour_bits_per_voxel", colour_bpv},
                          {"colour_format", colour_entries ? (cs.format == 1 ? "palette" : "raw") : "none"},
                          {"colour_palette_blocks", cs.blocks},
                          {"colour_palettes", cs.palettes},
                          {"colour_palette_entries", cs.palette_entries},
                          {"colour_materials", cs.materials},
                          {"colour_compression_rate", colour_rate}};
      if (pw)
        j["paging"] = {{"page_words", pw}, {"page_bytes", uint64_t{pw} * 4}, {"pages", pages},
                       {"node_order", node_order_name(f.paging.order)}, {"paged_words", f.paged_words},
                       {"size_ratio", bytes == 0 ? 1.0 : 4.0 * double(f.paged_words) / double(bytes)},
                       {"size_plane", f.size_plane}};
      else
        j["paging"] = nullptr;
      std::cout << j.dump(2) << "\n";
      return;
    }
    // Levels count up from the voxels (0) to the root (L, a 2^L grid): L + 1 rows below.
    std::printf("%s: %s, %u^3, %u levels (voxels 0 .. root %u), %llu voxels, valid\n", path->c_str(),
                encoding_name(f.dag.encoding).c_str(), f.grid.resolution, f.dag.levels + 1, f.dag.levels,
                (unsigned long long)f.voxels);
    std::printf("  grid origin (%g, %g, %g), voxel size %g; model bounds (%g, %g, %g) - (%g, %g, %g)\n",
                f.grid.origin[0], f.grid.origin[1], f.grid.origin[2], f.grid.voxel_size, f.bounds.lo[0],
                f.bounds.lo[1], f.bounds.lo[2], f.bounds.hi[0], f.bounds.hi[1], f.bounds.hi[2]);
    std::printf("  %-6s %14s %14s\n", "level", "octree nodes", "DAG nodes");
    for (size_t l = 0; l < f.dag_nodes.size(); ++l)
      std::printf("  %-6zu %14llu %14llu\n", l, (unsigned long long)f.svo_nodes[l], (unsigned long long)f.dag_nodes[l]);
    std::printf("  DAG nodes (levels >= 2): %llu; encoded %llu bytes, %.3f bits per voxel\n",
                (unsigned long long)total, (unsigned long long)bytes, bpv);
    if (colour_entries && cs.format == 1)
      std::printf("  colours: palette RGB24 (%u-bit colours), %llu entries (voxels and inner nodes, depth-first), %llu bytes, %.3f bits "
                  "per voxel, %.2f%% of raw; %llu blocks, %llu palettes, %llu palette entries, %llu distinct "
                  "colours; checked\n", f.colour_bits, (unsigned long long)colour_entries, (unsigned long long)colour_bytes,
                  colour_bpv, 100.0 * colour_rate, (unsigned long long)cs.blocks, (unsigned long long)cs.palettes,
                  (unsigned long long)cs.palette_entries, (unsigned long long)cs.materials);
    else if (colour_entries)
      std::printf("  colours: raw RGB24 (%u-bit colours), %llu entries (voxels and inner nodes, depth-first), %llu "
                  "bytes, %.3f bits per voxel; checked\n", f.colour_bits, (unsigned long long)colour_entries, (unsigned long long)colour_bytes,
                  colour_bpv);
    if (pw) {
      std::printf("  paged: %u-word pages (%u KiB), %llu pages, %s order, %llu words with padding (x%.4f); every "
                  "page checked\n", pw, pw / 256, (unsigned long long)pages, node_order_name(f.paging.order).c_str(),
                  (unsigned long long)f.paged_words,
                  bytes == 0 ? 1.0 : 4.0 * double(f.paged_words) / double(bytes));
      if (!f.colours.empty())
        std::printf(f.size_plane ? "  colours stream with the pages (their size plane, checked)\n"
                                 : "  colours render resident only (no size plane: written before .mvx version 5)\n");
    } else {
      std::printf("  not paged: renders resident only\n");
    }
  });
}

}  // namespace mv::cli
