#include "tiles3d_writer.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "atomic_dir.h"
#include "atomic_file.h"
#include "file_ops.h"
#include "glb_points.h"
#include "megavox/error.h"
#include "pnts_file.h"
#include "tiles3d_layout.h"
#include "tiles3d_place.h"
#include "tiles3d_properties.h"

namespace mv::io {

namespace {

using nlohmann::json;

// 16-bit colour (LAS) unless every value fits 8 bits (PLY uchar, or LAS files that store 8-bit values).
int colour_shift(const PointHierarchy& h) {
  const auto& rgb = h.points.rgb;
  return std::any_of(rgb.begin(), rgb.end(), [](uint16_t v) { return v > 255; }) ? 8 : 0;
}

double t3w_world(const PointHierarchy& h, size_t at, int a) {
  return h.source.offset[a] + h.source.scale[a] * static_cast<double>(h.points.xyz[at]);
}

std::vector<uint8_t> t3w_rgb(const PointHierarchy& h, const PointNode& n, int shift) {
  std::vector<uint8_t> rgb;
  if (!(h.source.attributes & kPointRgb)) return rgb;
  rgb.resize(3 * size_t{n.point_count});
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<uint8_t>(h.points.rgb[3 * n.first_point + i] >> shift);
  return rgb;
}

std::vector<PointProperty> t3w_properties(const PointHierarchy& h, const PointNode& n, const TileProperties& props) {
  std::vector<PointProperty> out;
  for (const TileProperty& p : props.properties)
    out.push_back({p.name, p.type, tile_property_values(h, p, n.first_point, n.point_count)});
  return out;
}

// 1.0: positions relative to the node's cube centre, in the input's coordinates.
PntsTile t3w_pnts(const PointHierarchy& h, const PointNode& n, const TileLayout& t, int shift,
                   const TileProperties& props) {
  PntsTile tile;
  std::copy(t.center, t.center + 3, tile.rtc_center);
  tile.positions.resize(3 * size_t{n.point_count});
  for (size_t i = 0; i < tile.positions.size(); ++i) {
    const int a = static_cast<int>(i % 3);
    // World in double first, then the small difference to the centre in float.
    tile.positions[i] = static_cast<float>(t3w_world(h, 3 * n.first_point + i, a) - t.center[a]);
  }
  tile.rgb = t3w_rgb(h, n, shift);
  tile.properties = t3w_properties(h, n, props);
  return tile;
}

// 1.1: positions in the tileset's local frame (z-up; the encoder turns them into glTF's y-up).
GlbPoints t3w_glb(const PointHierarchy& h, const PointNode& n, const TilePlacement& place, int shift,
                   const TileProperties& props) {
  GlbPoints g;
  g.positions.resize(3 * size_t{n.point_count});
  for (size_t i = 0; i < g.positions.size(); ++i) {
    const int a = static_cast<int>(i % 3);
    const double local = (t3w_world(h, 3 * n.first_point + i, a) - place.origin[a]) * place.units_to_metres[a];
    g.positions[i] = static_cast<float>(local);
  }
  g.rgb = t3w_rgb(h, n, shift);
  g.properties = t3w_properties(h, n, props);
  g.feature_id_property = props.classification;
  return g;
}

json t3w_box(const double c[3], const double half[3]) {
  return {c[0], c[1], c[2], half[0], 0, 0, 0, half[1], 0, 0, 0, half[2]};
}

json tile_json(const PointHierarchy& h, const std::vector<TileLayout>& tiles, size_t i, const char* ext) {
  const PointNode& n = h.nodes[i];
  const TileLayout& t = tiles[i];
  json j = {{"boundingVolume", {{"box", t3w_box(t.center, t.half)}}}, {"geometricError", t.geometric_error}};
  if (n.point_count) j["content"] = {{"uri", "tiles/" + t.name + ext}};
  if (!n.leaf()) {
    json children = json::array();
    for (int c = 0; c < std::popcount(n.child_mask); ++c)
      children.push_back(tile_json(h, tiles, n.first_child + c, ext));
    j["children"] = std::move(children);
  }
  return j;
}

json t3w_nullable(const std::string& s) { return s.empty() ? json(nullptr) : json(s); }

void t3w_property_extras(const TileProperties& props, json& extras) {
  json names = json::array(), skipped = json::array();
  for (const TileProperty& p : props.properties) names.push_back(p.name);
  for (const TileSkipped& s : props.skipped) skipped.push_back({{"name", s.name}, {"reason", s.reason}});
  extras["properties"] = std::move(names);
  if (props.classification >= 0) extras["featureIdProperty"] = props.properties[props.classification].name;
  if (!skipped.empty()) extras["skippedProperties"] = std::move(skipped);
}

json tileset_v10(const PointHierarchy& h, const std::vector<TileLayout>& tiles, const TileProperties& props,
                 const std::string& crs) {
  json root = tile_json(h, tiles, 0, ".pnts");
  root["refine"] = "REPLACE";
  json extras = {{"generator", "megavox"},
                 {"crs", t3w_nullable(crs.empty() ? h.source.crs : crs)},
                 {"upAxis", h.source.z_up ? "Z" : "Y"},
                 {"points", h.points_kept}};
  if (!h.source.format.empty()) extras["source"] = h.source.format;
  t3w_property_extras(props, extras);
  return {{"asset", {{"version", "1.0"}, {"extras", std::move(extras)}}},
          {"geometricError", tileset_geometric_error(tiles)},
          {"root", std::move(root)}};
}

json tileset_v11(const PointHierarchy& h, const std::vector<TileLayout>& tiles, const TileProperties& props,
                 const TilePlacement& place) {
  json root = tile_json(h, tiles, 0, ".glb");
  // The root's box: the points' bounds about the origin (at least half a grid step thick on every axis).
  double c[3], half[3];
  for (int a = 0; a < 3; ++a) {
    const double hw = std::max((place.hi[a] - place.lo[a]) / 2, std::abs(h.source.scale[a]) / 2);
    c[a] = (place.lo[a] + (place.hi[a] - place.lo[a]) / 2 - place.origin[a]) * place.units_to_metres[a];
    half[a] = hw * place.units_to_metres[a];
  }
  root["boundingVolume"] = {{"box", t3w_box(c, half)}};
  root["transform"] = json(std::vector<double>(place.transform, place.transform + 16));
  root["refine"] = "REPLACE";
  json extras = {{"generator", "megavox"},
                 {"crs", t3w_nullable(place.crs)},
                 {"declaredCrs", t3w_nullable(place.declared)},
                 {"placement", place.placed() ? "EPSG:4978" : "local"}};
  if (place.placed()) {
    extras["crsName"] = place.crs_name;
    extras["placementErrorMetres"] = place.error_metres;
    extras["placementVerticalErrorMetres"] = place.vertical_error_metres;
  }
  if (!place.note.empty()) extras["placementNote"] = place.note;
  extras["localOrigin"] = {place.origin[0], place.origin[1], place.origin[2]};
  extras["unitsToMetres"] = {place.units_to_metres[0], place.units_to_metres[1], place.units_to_metres[2]};
  extras["upAxis"] = place.placed() || h.source.z_up ? "Z" : "Y";
  extras["points"] = h.points_kept;
  if (!h.source.format.empty()) extras["source"] = h.source.format;
  t3w_property_extras(props, extras);
  return {{"asset", {{"version", "1.1"}, {"extras", std::move(extras)}}},
          {"geometricError", tileset_geometric_error(tiles)},
          {"root", std::move(root)}};
}

void write_bytes(const std::string& path, const void* data, size_t bytes) {
  write_atomically(path, [&](std::FILE* f) { return write_all(f, data, bytes); });
}

void check_version(const std::string& dir, const Tiles3dOptions& o) {
  if (o.minor_version != 0 && o.minor_version != 1)
    throw CodedError(ErrorCode::invalid_argument, "cannot write '" + dir + "': 3D Tiles 1." +
                                                      std::to_string(o.minor_version) +
                                                      " is not a version megavox writes (1.0 or 1.1)");
}

// The frame a 1.1 tileset's boxes and positions are given in.
TileFrame frame_of(const TilePlacement& place) {
  TileFrame frame;
  std::copy(place.origin, place.origin + 3, frame.origin);
  std::copy(place.units_to_metres, place.units_to_metres + 3, frame.factor);
  return frame;
}

// A node's tile (none for a node without points) into tmp/tiles.
void write_tile(const std::string& tmp, const PointHierarchy& h, const PointNode& n, const TileLayout& t,
                const Tiles3dOptions& o, const TilePlacement& place, int shift, const TileProperties& props) {
  if (!n.point_count) return;  // a tile without content
  const bool v11 = o.minor_version == 1;
  const std::string name = tmp + "/tiles/" + t.name + (v11 ? ".glb" : ".pnts");
  const std::vector<uint8_t> bytes = v11 ? encode_glb_points(t3w_glb(h, n, place, shift, props), o.meshopt)
                                         : encode_pnts(t3w_pnts(h, n, t, shift, props));
  write_bytes(name, bytes.data(), bytes.size());
}

}  // namespace

void write_3dtiles(const std::string& dir, const PointHierarchy& h, const Tiles3dOptions& o) {
  write_3dtiles(dir, h, o, Tiles3dShare{});
}

void write_3dtiles(const std::string& dir, const PointHierarchy& h, const Tiles3dOptions& o, const Tiles3dShare& share) {
  check_version(dir, o);
  const bool v11 = o.minor_version == 1;
  // Everything that can refuse the input comes before anything is written: the hierarchy, the properties, the CRS.
  std::vector<TileLayout> tiles;
  TileProperties props;
  TilePlacement place;
  // The hierarchy's faults are the builder's (unknown); a CRS PROJ cannot place is the caller's (invalid_argument).
  ErrorCode fault = ErrorCode::unknown;
  try {
    tiles = tiles3d_layout(h, {}, share.elsewhere);  // checks the hierarchy
    props = tile_properties(h);
    if (v11) {
      fault = ErrorCode::invalid_argument;
      place = share.start ? tiles3d_place(h.source, share.lo, share.hi, o.crs) : tiles3d_place(h, o.crs);
      tiles = tiles3d_layout(h, frame_of(place), share.elsewhere);
    }
  } catch (const Error& e) {
    throw CodedError(classify_or(e, fault), "cannot write '" + dir + "': " + e.what(), error_settings(e));
  }
  const int shift = share.start ? (share.wide_colour ? 8 : 0) : colour_shift(h);
  write_dir_atomically(dir, "tileset.json", [&](const std::string& tmp) {
    std::filesystem::create_directory(tmp + "/tiles");
    if (share.start) share.start(tmp, shift);
    for (size_t i = 0; i < h.nodes.size(); ++i)
      if (share.elsewhere.empty() || !share.elsewhere[i]) write_tile(tmp, h, h.nodes[i], tiles[i], o, place, shift, props);
    if (share.finish) share.finish();
    const json ts = v11 ? tileset_v11(h, tiles, props, place) : tileset_v10(h, tiles, props, o.crs);
    const std::string text = ts.dump() + "\n";  // compact: one object per node adds up
    write_bytes(tmp + "/tileset.json", text.data(), text.size());
  });
}

void write_3dtiles_part(const std::string& tmp_dir, const PointHierarchy& part, const Tiles3dOptions& o,
                        const int64_t lo[3], const int64_t hi[3], int colour_shift) {
  check_version(tmp_dir, o);
  const TileProperties props = tile_properties(part);
  const TilePlacement place = o.minor_version == 1 ? tiles3d_place(part.source, lo, hi, o.crs) : TilePlacement{};
  const TileFrame frame = o.minor_version == 1 ? frame_of(place) : TileFrame{};
  for (const PointNode& n : part.nodes) write_tile(tmp_dir, part, n, tile_box(part, n, frame), o, place, colour_shift, props);
}

}  // namespace mv::io
