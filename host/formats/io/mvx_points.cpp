// The point content of .mvx files (layout in include/megavox/mvx.h): written whole, read with every section
// and the hierarchy's structure checked.
#include <bit>
#include <cmath>
#include <tuple>
#include <cstring>

#include <nlohmann/json.hpp>

#include "megavox/error.h"
#include "megavox/mvx.h"
#include "mvx_format.h"

namespace mv {

using namespace mvx_format;

static_assert(sizeof(PointNode) == 40, ".mvx stores point nodes as 40 bytes");

namespace {

struct PointMeta {
  uint32_t attributes, extra_bytes, z_up;
  int32_t shift;
  uint32_t depth, crs_bytes, format_bytes, grid_bits;
  double scale[3], offset[3];
  int64_t cube_min[3];
  uint64_t points_in, points_kept, points_dropped, nodes, stored_points;
};
static_assert(sizeof(PointMeta) == 32 + 48 + 24 + 40);

// Every node's points, wherever they are held.
uint64_t stored_points(const PointHierarchy& h) {
  uint64_t n = 0;
  for (const PointNode& node : h.nodes) n += node.point_count;
  return n;
}

std::string fields_json(const PointCloudInfo& info) {
  if (info.fields.empty() || !(info.attributes & kPointExtra)) return {};
  nlohmann::json a = nlohmann::json::array();
  for (const PointField& f : info.fields)
    a.push_back({{"name", f.name}, {"type", point_field_type_name(f.type)}, {"offset", f.offset}, {"count", f.count},
                 {"scale", f.scale}, {"add", f.add}, {"description", f.description}});
  return a.dump();
}

// The fields section, every field checked to lie inside the `record`-byte extra record.
std::vector<PointField> parse_fields(const std::string& text, uint32_t record, const std::string& path) {
  auto fail = [&](const std::string& what) -> std::vector<PointField> {
    throw Error(path + ": bad point fields section: " + what);
  };
  const nlohmann::json a = nlohmann::json::parse(text, nullptr, false);
  if (!a.is_array()) return fail("not a JSON array");
  std::vector<PointField> out;
  try {
    for (const nlohmann::json& j : a) {
      PointField f;
      f.name = j.at("name").get<std::string>();
      const std::string type = j.at("type").get<std::string>();
      int t = 0;
      while (t < 10 && type != point_field_type_name(static_cast<PointFieldType>(t))) ++t;
      if (t == 10) return fail("unknown type '" + type.substr(0, 16) + "'");
      f.type = static_cast<PointFieldType>(t);
      f.offset = j.at("offset").get<uint32_t>();
      f.count = j.at("count").get<uint32_t>();
      f.scale = j.at("scale").get<double>();
      f.add = j.at("add").get<double>();
      f.description = j.at("description").get<std::string>();
      if (f.name.empty() || f.name.size() > 64) return fail("a name of " + std::to_string(f.name.size()) + " characters");
      if (f.count == 0 || uint64_t{f.offset} + uint64_t{point_field_size(f.type)} * f.count > record)
        return fail("'" + f.name + "' lies outside the " + std::to_string(record) + "-byte record");
      out.push_back(std::move(f));
    }
  } catch (const nlohmann::json::exception&) {
    return fail("a field lacks a name, type, offset, count, scale, add or description of the right kind");
  }
  return out;
}

// The hierarchy's structure: what a reader relies on to walk it without further checks. `elsewhere`: nodes whose
// points h does not hold (PointsElsewhere); at each level they follow those it holds.
void validate(const PointHierarchy& h, const std::string& path, const std::vector<bool>& elsewhere = {}) {
  auto fail = [&](const std::string& what) { throw Error(path + ": bad point hierarchy: " + what); };
  const uint64_t n = h.nodes.size();
  if (n == 0 || h.nodes[0].code != 1 || h.nodes[0].level != 0) fail("no root node");
  if (h.depth > 21) fail("depth " + std::to_string(h.depth) + " over 21");
  const uint64_t stored = stored_points(h);
  uint64_t next_child = 1, next_point = 0, leaf_points = 0, held = 0;
  std::vector<uint64_t> per_level(h.depth + 1, 0);
  std::vector<bool> level_elsewhere(h.depth + 1, false);  // a node of the level was elsewhere already
  if (!elsewhere.empty() && elsewhere.size() != n) fail("the nodes held elsewhere are not marked node by node");
  for (uint64_t i = 0; i < n; ++i) {
    const PointNode& node = h.nodes[i];
    const std::string at = "node " + std::to_string(i);
    if (node.level <= h.depth) {
      const bool away = !elsewhere.empty() && elsewhere[i];
      if (!away && level_elsewhere[node.level]) fail(at + " is held here but follows nodes held elsewhere");
      if (away) level_elsewhere[node.level] = true;
      else if ((held += node.point_count) > h.points.size()) fail(at + "'s points are not the next ones in node order");
    }
    if (node.level > h.depth || std::bit_width(node.code) != 3u * node.level + 1) fail(at + "'s code and level disagree");
    if (node.first_point != next_point || node.point_count > stored - next_point)
      fail(at + "'s points are not the next ones in node order");
    next_point += node.point_count;
    ++per_level[node.level];
    if (node.leaf()) {
      if (node.point_count != node.subtree_points) fail(at + " is a leaf whose points are not its subtree's");
      leaf_points += node.point_count;
      continue;
    }
    const uint32_t children = static_cast<uint32_t>(std::popcount(node.child_mask));
    if (node.first_child != next_child || uint64_t{node.first_child} + children > n)
      fail(at + "'s children are not the next nodes in breadth-first order");
    next_child += children;
    uint64_t sum = 0;
    uint32_t c = node.first_child;
    for (uint32_t o = 0; o < 8; ++o)
      if (node.child_mask >> o & 1) {
        if (h.nodes[c].code != ((node.code << 3) | o)) fail(at + "'s child " + std::to_string(o) + " has another code");
        sum += h.nodes[c++].subtree_points;
      }
    if (sum != node.subtree_points || node.point_count > node.subtree_points) fail(at + "'s point counts disagree");
  }
  if (next_child != n) fail(std::to_string(n - next_child) + " nodes are nobody's children");
  if (next_point != stored) fail("points after the last node's");
  if (held != h.points.size()) fail("it holds " + std::to_string(h.points.size()) + " points, but its nodes in node order hold " + std::to_string(held));
  if (leaf_points != h.points_kept) fail("the leaves hold " + std::to_string(leaf_points) + " points, not the " +
                                         std::to_string(h.points_kept) + " kept");
  if (per_level != h.nodes_per_level) fail("the nodes per level disagree with the node table");
}

}  // namespace

void write_mvx_points(const std::string& path, const PointHierarchy& h) { write_mvx_points(path, h, PointsElsewhere{}); }

void write_mvx_points(const std::string& path, const PointHierarchy& h, const PointsElsewhere& share) {
  validate(h, path, share.elsewhere);
  PointMeta meta{};
  const PointCloudInfo& info = h.source;
  meta.attributes = info.attributes;
  meta.extra_bytes = info.extra_bytes;
  meta.z_up = info.z_up ? 1 : 0;
  meta.shift = h.shift;
  meta.depth = h.depth;
  meta.grid_bits = h.grid_bits;
  meta.crs_bytes = static_cast<uint32_t>(info.crs.size());
  meta.format_bytes = static_cast<uint32_t>(info.format.size());
  for (int a = 0; a < 3; ++a) {
    meta.scale[a] = info.scale[a];
    meta.offset[a] = info.offset[a];
    meta.cube_min[a] = h.cube_min[a];
  }
  meta.points_in = h.points_in;
  meta.points_kept = h.points_kept;
  meta.points_dropped = h.points_dropped;
  meta.nodes = h.nodes.size();
  const uint64_t stored = stored_points(h);
  meta.stored_points = stored;
  std::vector<char> meta_bytes(sizeof meta + info.crs.size() + info.format.size());
  std::memcpy(meta_bytes.data(), &meta, sizeof meta);
  std::memcpy(meta_bytes.data() + sizeof meta, info.crs.data(), info.crs.size());
  std::memcpy(meta_bytes.data() + sizeof meta + info.crs.size(), info.format.data(), info.format.size());

  // This process's points of each level: where they start in h.points and how many.
  std::vector<uint64_t> own_first(h.depth + 1, 0), own_count(h.depth + 1, 0);
  uint64_t own = 0;
  for (size_t i = 0; i < h.nodes.size(); ++i) {
    if (!share.elsewhere.empty() && share.elsewhere[i]) continue;
    const PointNode& n = h.nodes[i];
    if (own_count[n.level] == 0) own_first[n.level] = own;
    own_count[n.level] += n.point_count;
    own += n.point_count;
  }
  const auto whole = [](uint32_t kind, const void* data, uint64_t bytes) {
    return StreamedBlob{kind, bytes, [data, bytes](const PutBytes& put) { put(data, bytes); }};
  };
  // A point column: per level, this process's points, then the others'.
  const auto column = [&](uint32_t kind, PointColumn c, const void* data, uint64_t per_point) {
    return StreamedBlob{kind, stored * per_point, [&, c, data, per_point](const PutBytes& put) {
                          for (uint32_t l = 0; l <= h.depth; ++l) {
                            put(static_cast<const char*>(data) + own_first[l] * per_point, own_count[l] * per_point);
                            if (share.others) share.others(c, l, put);
                          }
                        }};
  };
  const PointColumns& p = h.points;
  std::vector<StreamedBlob> blobs = {whole(kSecPointMeta, meta_bytes.data(), meta_bytes.size()),
                                     whole(kSecPointLevels, h.nodes_per_level.data(), h.nodes_per_level.size() * 8),
                                     whole(kSecPointNodes, h.nodes.data(), h.nodes.size() * sizeof(PointNode)),
                                     column(kSecPointXyz, PointColumn::xyz, p.xyz.data(), 12)};
  if (info.attributes & kPointRgb) blobs.push_back(column(kSecPointRgb, PointColumn::rgb, p.rgb.data(), 6));
  if (info.attributes & kPointNormal) blobs.push_back(column(kSecPointNormal, PointColumn::normal, p.normal.data(), 12));
  if (info.attributes & kPointIntensity)
    blobs.push_back(column(kSecPointIntensity, PointColumn::intensity, p.intensity.data(), 2));
  if (info.attributes & kPointExtra) blobs.push_back(column(kSecPointExtra, PointColumn::extra, p.extra.data(), info.extra_bytes));
  const std::string fields = fields_json(info);
  if (!fields.empty()) blobs.push_back(whole(kSecPointFields, fields.data(), fields.size()));

  Header hd{};
  hd.version = kMvxVersion;
  hd.content = kPoints;
  hd.levels = h.depth;
  hd.voxels = h.points_kept;
  const double side = std::ldexp(1.0, 21 + static_cast<int>(h.shift));
  for (int a = 0; a < 3; ++a) {
    hd.bounds_lo[a] = info.offset[a] + info.scale[a] * static_cast<double>(h.cube_min[a]);
    hd.bounds_hi[a] = hd.bounds_lo[a] + info.scale[a] * side;
  }
  write_file(path, hd, blobs);
}

PointHierarchy read_mvx_points(const std::string& path) {
  Opened o = open_file(path);
  if (o.header.content != kPoints)
    throw Error(path + ": holds voxels, not a point cloud: use `megavox info` or `megavox render`");
  for (uint32_t k : {kCounts, kLevels, kNodes, kInner, kBricks})
    if (o.find[k]) throw Error(path + ": bad section table (voxel sections in a point file)");
  for (uint32_t k : {kSecPointMeta, kSecPointLevels, kSecPointNodes, kSecPointXyz})
    if (!o.find[k]) throw Error(path + ": bad section table (a point section is missing)");
  std::FILE* f = o.file.get();
  std::vector<char> mb = section_data<char>(f, *o.find[kSecPointMeta], path, "point meta");
  PointMeta meta;
  if (mb.size() < sizeof meta) throw Error(path + ": the point meta section is too short");
  std::memcpy(&meta, mb.data(), sizeof meta);
  if (mb.size() != sizeof meta + uint64_t{meta.crs_bytes} + meta.format_bytes)
    throw Error(path + ": the point meta section's text lengths disagree with its size");
  const uint32_t known = kPointRgb | kPointNormal | kPointIntensity | kPointExtra;
  if (meta.attributes & ~known) throw Error(path + ": unknown point attributes " + std::to_string(meta.attributes));
  if (meta.extra_bytes > 65535) throw Error(path + ": bad extra byte count in the point meta section");
  if (meta.grid_bits < 1 || meta.grid_bits > 10) throw Error(path + ": bad node grid in the point meta section");
  if (meta.depth > 21 || meta.shift > 32 || meta.shift < -21) throw Error(path + ": bad depth or cube in the point meta section");
  PointHierarchy h;
  PointCloudInfo& info = h.source;
  info.attributes = meta.attributes;
  info.extra_bytes = meta.extra_bytes;
  info.z_up = meta.z_up != 0;
  info.crs.assign(mb.data() + sizeof meta, meta.crs_bytes);
  info.format.assign(mb.data() + sizeof meta + meta.crs_bytes, meta.format_bytes);
  info.points = meta.points_in;
  for (int a = 0; a < 3; ++a) {
    info.scale[a] = meta.scale[a];
    info.offset[a] = meta.offset[a];
    h.cube_min[a] = meta.cube_min[a];
  }
  h.shift = meta.shift;
  h.depth = meta.depth;
  h.grid_bits = meta.grid_bits;
  h.points_in = meta.points_in;
  h.points_kept = meta.points_kept;
  h.points_dropped = meta.points_dropped;
  if (meta.points_kept + meta.points_dropped != meta.points_in)
    throw Error(path + ": points in, kept and dropped do not add up");

  // Sizes first: a section must hold exactly what the meta says before anything is read.
  auto expect = [&](uint32_t kind, uint64_t bytes, const char* what) {
    const Section* s = o.find[kind];
    if (s && s->bytes != bytes)
      throw Error(path + ": the " + std::string(what) + " section holds " + std::to_string(s->bytes) +
                  " bytes, not the " + std::to_string(bytes) + " its counts need");
  };
  const uint64_t np = meta.stored_points;
  if (meta.nodes > o.find[kSecPointNodes]->bytes || np > o.find[kSecPointXyz]->bytes)
    throw Error(path + ": counts larger than the file holds");
  expect(kSecPointNodes, meta.nodes * sizeof(PointNode), "point nodes");
  expect(kSecPointLevels, (uint64_t{meta.depth} + 1) * 8, "nodes per level");
  expect(kSecPointXyz, np * 12, "positions");
  const std::pair<PointAttribute, SectionKind> columns[] = {
      {kPointRgb, kSecPointRgb}, {kPointNormal, kSecPointNormal},
      {kPointIntensity, kSecPointIntensity}, {kPointExtra, kSecPointExtra}};
  const uint64_t column_bytes[] = {np * 6, np * 12, np * 2, np * meta.extra_bytes};
  const char* column_names[] = {"colour", "normal", "intensity", "extra bytes"};
  for (int c = 0; c < 4; ++c) {
    const bool has = meta.attributes & columns[c].first;
    if (has != (o.find[columns[c].second] != nullptr))
      throw Error(path + ": the " + column_names[c] + " section disagrees with the attributes");
    expect(columns[c].second, column_bytes[c], column_names[c]);
  }
  h.nodes_per_level = section_data<uint64_t>(f, *o.find[kSecPointLevels], path, "nodes per level");
  h.nodes = section_data<PointNode>(f, *o.find[kSecPointNodes], path, "point nodes");
  h.points.xyz = section_data<int32_t>(f, *o.find[kSecPointXyz], path, "positions");
  if (o.find[kSecPointRgb]) h.points.rgb = section_data<uint16_t>(f, *o.find[kSecPointRgb], path, "colour");
  if (o.find[kSecPointNormal]) h.points.normal = section_data<float>(f, *o.find[kSecPointNormal], path, "normal");
  if (o.find[kSecPointIntensity])
    h.points.intensity = section_data<uint16_t>(f, *o.find[kSecPointIntensity], path, "intensity");
  if (o.find[kSecPointExtra]) h.points.extra = section_data<uint8_t>(f, *o.find[kSecPointExtra], path, "extra bytes");
  if (o.find[kSecPointFields]) {
    if (!o.find[kSecPointExtra]) throw Error(path + ": point fields without extra bytes");
    const std::vector<char> text = section_data<char>(f, *o.find[kSecPointFields], path, "point fields");
    info.fields = parse_fields(std::string(text.begin(), text.end()), info.extra_bytes, path);
  }
  validate(h, path);
  return h;
}

}  // namespace mv
