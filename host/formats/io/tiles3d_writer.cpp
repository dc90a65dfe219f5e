#include "tiles3d_writer.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <filesystem>

#include "atomic_dir.h"
#include "atomic_file.h"
#include "file_ops.h"
#include "pnts_file.h"
#include "tiles3d_layout.h"

namespace mv::io {

namespace {

using nlohmann::json;

// 16-bit colour (LAS) unless every value fits 8 bits (PLY uchar, or LAS files that store 8-bit values).
int colour_shift(const PointHierarchy& h) {
  const auto& rgb = h.points.rgb;
  return std::any_of(rgb.begin(), rgb.end(), [](uint16_t v) { return v > 255; }) ? 8 : 0;
}

PntsTile node_tile(const PointHierarchy& h, const PointNode& n, const TileLayout& t, int shift) {
  PntsTile tile;
  std::copy(t.center, t.center + 3, tile.rtc_center);
  tile.positions.resize(3 * size_t{n.point_count});
  const bool rgb = h.source.attributes & kPointRgb;
  if (rgb) tile.rgb.resize(3 * size_t{n.point_count});
  for (size_t i = 0; i < 3 * size_t{n.point_count}; ++i) {
    const size_t at = 3 * n.first_point + i;
    const int a = static_cast<int>(i % 3);
    // World in double first, then the small difference to the centre in float.
    const double world = h.source.offset[a] + h.source.scale[a] * static_cast<double>(h.points.xyz[at]);
    tile.positions[i] = static_cast<float>(world - t.center[a]);
    if (rgb) tile.rgb[i] = static_cast<uint8_t>(h.points.rgb[at] >> shift);
  }
  return tile;
}

json tile_json(const PointHierarchy& h, const std::vector<TileLayout>& tiles, size_t i) {
  const PointNode& n = h.nodes[i];
  const TileLayout& t = tiles[i];
  json j = {{"boundingVolume",
             {{"box", {t.center[0], t.center[1], t.center[2], t.half[0], 0, 0, 0, t.half[1], 0, 0, 0, t.half[2]}}}},
            {"geometricError", t.geometric_error}};
  if (n.point_count) j["content"] = {{"uri", "tiles/" + t.name + ".pnts"}};
  if (!n.leaf()) {
    json children = json::array();
    for (int c = 0; c < std::popcount(n.child_mask); ++c) children.push_back(tile_json(h, tiles, n.first_child + c));
    j["children"] = std::move(children);
  }
  return j;
}

json tileset_json(const PointHierarchy& h, const std::vector<TileLayout>& tiles) {
  json root = tile_json(h, tiles, 0);
  root["refine"] = "REPLACE";
  json extras = {{"generator", "megavox"},
                 {"crs", h.source.crs.empty() ? json(nullptr) : json(h.source.crs)},
                 {"upAxis", h.source.z_up ? "Z" : "Y"},
                 {"points", h.points_kept}};
  if (!h.source.format.empty()) extras["source"] = h.source.format;
  return {{"asset", {{"version", "1.0"}, {"extras", std::move(extras)}}},
          {"geometricError", tileset_geometric_error(tiles)},
          {"root", std::move(root)}};
}

void write_bytes(const std::string& path, const void* data, size_t bytes) {
  write_atomically(path, [&](std::FILE* f) { return write_all(f, data, bytes); });
}

}  // namespace

void write_3dtiles(const std::string& dir, const PointHierarchy& h) {
  const std::vector<TileLayout> tiles = tiles3d_layout(h);  // checks the hierarchy before anything is written
  const int shift = colour_shift(h);
  write_dir_atomically(dir, "tileset.json", [&](const std::string& tmp) {
    std::filesystem::create_directory(tmp + "/tiles");
    for (size_t i = 0; i < h.nodes.size(); ++i) {
      if (!h.nodes[i].point_count) continue;  // a tile without content
      const std::vector<uint8_t> bytes = encode_pnts(node_tile(h, h.nodes[i], tiles[i], shift));
      write_bytes(tmp + "/tiles/" + tiles[i].name + ".pnts", bytes.data(), bytes.size());
    }
    const std::string text = tileset_json(h, tiles).dump() + "\n";  // compact: one object per node adds up
    write_bytes(tmp + "/tileset.json", text.data(), text.size());
  });
}

}  // namespace mv::io
