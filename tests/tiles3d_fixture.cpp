#include "tiles3d_fixture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <deque>
#include <memory>
#include <random>
#include <vector>

namespace mv::test {

namespace {

struct Point {
  std::array<int32_t, 3> xyz;
  std::array<uint16_t, 3> rgb;
  uint16_t intensity = 0;
  std::array<uint8_t, kSyntheticRecordBytes> record{};
};

template <class T>
void t3f_put(std::array<uint8_t, kSyntheticRecordBytes>& r, uint32_t at, T v) {
  std::memcpy(r.data() + at, &v, sizeof v);
}

// The record of point i (synthetic_fields' layout): values that vary with the point and its position.
void t3f_fill_record(Point& p, uint32_t i, std::mt19937_64& rng) {
  auto& r = p.record;
  t3f_put<uint8_t>(r, 0, static_cast<uint8_t>(p.xyz[2] & 1 ? 2 : (i % 7 == 0 ? 6 : 5)));  // classification
  t3f_put<uint8_t>(r, 1, static_cast<uint8_t>(1 + i % 3));                              // return_number
  t3f_put<float>(r, 2, static_cast<float>(int(i % 61) - 30) * 0.5f);                    // scan_angle
  t3f_put<double>(r, 6, 271828.0 + 0.001 * i + 1e-6 * (i % 13));                        // gps_time
  t3f_put<uint16_t>(r, 14, static_cast<uint16_t>(100 + i % 4));                         // point_source_id
  t3f_put<uint64_t>(r, 16, (uint64_t{1} << 60) + i);                                    // serial (u64)
  t3f_put<int16_t>(r, 24, static_cast<int16_t>(int(rng() % 2001) - 1000));              // Pulse width (scaled)
  for (uint32_t k = 0; k < 3; ++k) t3f_put<uint16_t>(r, 26 + 2 * k, static_cast<uint16_t>(rng() & 0xffff));  // vec
  for (uint32_t k = 0; k < 5; ++k) t3f_put<uint8_t>(r, 32 + k, static_cast<uint8_t>(rng()));  // extra_bytes
  t3f_put<uint8_t>(r, 37, static_cast<uint8_t>(i & 0xff));                              // Intensity (a second one)
  p.intensity = static_cast<uint16_t>(rng() & 0xffff);
}

struct Node {
  uint64_t code = 1;
  uint32_t level = 0;
  std::vector<Point> points;  // a leaf's, or an inner node's representatives
  std::array<std::unique_ptr<Node>, 8> child;
};

// Cells of 21 bits per axis: (xyz - cube_min) >> shift; the octant at `level` is bit (20 - level) of each.
uint32_t octant(const Point& p, const int64_t* cube_min, uint32_t shift, uint32_t level) {
  uint32_t o = 0;
  for (int a = 0; a < 3; ++a) o |= static_cast<uint32_t>(((p.xyz[a] - cube_min[a]) >> shift >> (20 - level)) & 1) << a;
  return o;
}

void split(Node& n, std::vector<Point> pts, const SyntheticCloud& c, const int64_t* cube_min) {
  if (pts.size() <= c.capacity || n.level == c.max_level) {
    n.points = std::move(pts);
    return;
  }
  const size_t step = pts.size() / c.capacity + 1;
  for (size_t i = 0; i < pts.size(); i += step) n.points.push_back(pts[i]);
  std::array<std::vector<Point>, 8> parts;
  for (const Point& p : pts) parts[octant(p, cube_min, c.shift, n.level)].push_back(p);
  for (uint32_t o = 0; o < 8; ++o) {
    if (parts[o].empty()) continue;
    n.child[o] = std::make_unique<Node>();
    n.child[o]->code = n.code << 3 | o;
    n.child[o]->level = n.level + 1;
    split(*n.child[o], std::move(parts[o]), c, cube_min);
  }
}

// Three blobs of different spread and a sloping plane: dense and sparse parts, so leaves sit at several levels.
std::vector<Point> cloud(const SyntheticCloud& c, const int64_t* cube_min) {
  std::mt19937_64 rng(c.seed);
  const double side = std::ldexp(1.0, static_cast<int>(21 + c.shift));
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> unit;
  const double blobs[3][4] = {{0.3, 0.3, 0.3, 0.01}, {0.7, 0.6, 0.4, 0.05}, {0.2, 0.8, 0.7, 0.002}};
  const uint16_t top = c.colour == Colour::bits16 ? 65535 : 255;
  std::vector<Point> pts;
  for (uint32_t i = 0; i < c.points; ++i) {
    double u[3];
    if (i % 4 == 3) {
      u[0] = unit(rng), u[1] = unit(rng), u[2] = 0.2 + 0.5 * u[0];
    } else {
      const double* b = blobs[i % 4];
      for (int a = 0; a < 3; ++a) u[a] = b[a] + b[3] * gauss(rng);
    }
    Point p;
    for (int a = 0; a < 3; ++a) {
      const double g = std::clamp(u[a], 0.0, 1.0 - 1e-9) * side;
      p.xyz[a] = static_cast<int32_t>(cube_min[a] + static_cast<int64_t>(g));
      p.rgb[a] = c.colour == Colour::none ? 0 : static_cast<uint16_t>(std::clamp(u[a], 0.0, 1.0) * top);
    }
    if (c.fields) t3f_fill_record(p, i, rng);
    pts.push_back(p);
  }
  return pts;
}

}  // namespace

std::vector<PointField> synthetic_fields() {
  using T = PointFieldType;
  auto field = [](const char* name, T type, uint32_t offset, uint32_t count = 1, double scale = 1, double add = 0) {
    PointField f;
    f.name = name, f.type = type, f.offset = offset, f.count = count, f.scale = scale, f.add = add;
    return f;
  };
  return {field("classification", T::u8, 0), field("return_number", T::u8, 1), field("scan_angle", T::f32, 2),
          field("gps_time", T::f64, 6),      field("point_source_id", T::u16, 14), field("serial", T::u64, 16),
          field("Pulse width", T::i16, 24, 1, 0.1, 5), field("vec", T::u16, 26, 3),
          field("extra_bytes", T::u8, 32, 5), field("Intensity", T::u8, 37)};
}

PointHierarchy synthetic_hierarchy(const SyntheticCloud& c) {
  PointHierarchy h;
  h.source.format = "synthetic";
  h.source.attributes = c.colour == Colour::none ? 0u : uint32_t{kPointRgb};
  if (c.fields) {
    h.source.attributes |= kPointIntensity | kPointExtra;
    h.source.extra_bytes = kSyntheticRecordBytes;
    h.source.fields = synthetic_fields();
  }
  h.source.scale[0] = 0.001, h.source.scale[1] = 0.002, h.source.scale[2] = 0.0005;
  h.source.offset[0] = 500000.25, h.source.offset[1] = 5400000.5, h.source.offset[2] = -12.75;
  h.source.z_up = c.z_up;
  h.source.crs = c.crs;
  h.cube_min[0] = -1000000, h.cube_min[1] = -2000000, h.cube_min[2] = 12345;
  h.shift = c.shift;

  Node root;
  split(root, cloud(c, h.cube_min), c, h.cube_min);

  // Breadth-first: each node's children are appended together, so they are contiguous and in octant order.
  std::deque<const Node*> queue{&root};
  std::vector<const Node*> order;
  while (!queue.empty()) {
    const Node* n = queue.front();
    queue.pop_front();
    order.push_back(n);
    for (const auto& ch : n->child)
      if (ch) queue.push_back(ch.get());
  }
  size_t next_child = 1;
  for (const Node* n : order) {
    PointNode pn;
    pn.code = n->code;
    pn.level = static_cast<uint8_t>(n->level);
    pn.first_point = h.points.size();
    pn.point_count = static_cast<uint32_t>(n->points.size());
    for (uint32_t o = 0; o < 8; ++o)
      if (n->child[o]) pn.child_mask |= static_cast<uint8_t>(1u << o);
    if (pn.child_mask) {
      pn.first_child = static_cast<uint32_t>(next_child);
      next_child += static_cast<size_t>(__builtin_popcount(pn.child_mask));
    }
    for (const Point& p : n->points) {
      h.points.xyz.insert(h.points.xyz.end(), p.xyz.begin(), p.xyz.end());
      if (c.colour != Colour::none) h.points.rgb.insert(h.points.rgb.end(), p.rgb.begin(), p.rgb.end());
      if (c.fields) {
        h.points.intensity.push_back(p.intensity);
        h.points.extra.insert(h.points.extra.end(), p.record.begin(), p.record.end());
      }
    }
    if (pn.leaf()) h.points_kept += pn.point_count;
    h.depth = std::max<uint32_t>(h.depth, n->level);
    if (h.nodes_per_level.size() <= n->level) h.nodes_per_level.resize(n->level + 1);
    ++h.nodes_per_level[n->level];
    h.nodes.push_back(pn);
  }
  // Leaves' subtree counts are their points; an inner node's, the sum of its children's (children come later).
  for (size_t i = h.nodes.size(); i-- > 0;) {
    PointNode& n = h.nodes[i];
    if (n.leaf()) {
      n.subtree_points = n.point_count;
      continue;
    }
    for (int k = 0; k < __builtin_popcount(n.child_mask); ++k) n.subtree_points += h.nodes[n.first_child + k].subtree_points;
  }
  h.points_in = h.points_kept;
  return h;
}

std::vector<SyntheticProperty> synthetic_properties(const PointHierarchy& h) {
  if (!(h.source.attributes & kPointExtra)) return {};
  return {{"intensity", -1},        {"classification", 0},  {"return_number", 1}, {"scan_angle", 2},
          {"gps_time", 3, 0, false}, {"point_source_id", 4}, {"Pulse_width", 6, 0, false},
          {"vec_0", 7, 0},           {"vec_1", 7, 1},        {"vec_2", 7, 2},       {"Intensity_2", 9}};
}

std::vector<std::string> synthetic_skipped(const PointHierarchy& h) {
  if (!(h.source.attributes & kPointExtra)) return {};
  return {"serial", "extra_bytes"};
}

double synthetic_value(const PointHierarchy& h, const SyntheticProperty& p, uint64_t point) {
  if (p.field < 0) return h.points.intensity.at(point);
  const PointField& f = h.source.fields.at(p.field);
  const uint8_t* at =
      h.points.extra.data() + point * h.source.extra_bytes + f.offset + p.component * point_field_size(f.type);
  double v = 0;
  auto load = [&](auto x) {
    std::memcpy(&x, at, sizeof x);
    v = static_cast<double>(x);
  };
  switch (f.type) {
    case PointFieldType::u8: load(uint8_t{}); break;
    case PointFieldType::i8: load(int8_t{}); break;
    case PointFieldType::u16: load(uint16_t{}); break;
    case PointFieldType::i16: load(int16_t{}); break;
    case PointFieldType::u32: load(uint32_t{}); break;
    case PointFieldType::i32: load(int32_t{}); break;
    case PointFieldType::u64: load(uint64_t{}); break;
    case PointFieldType::i64: load(int64_t{}); break;
    case PointFieldType::f32: load(float{}); break;
    case PointFieldType::f64: load(double{}); break;
  }
  return v * f.scale + f.add;
}

std::string tile_name(uint64_t code, uint32_t level) {
  std::string s = "r";
  for (uint32_t l = level; l-- > 0;) s += char('0' + ((code >> (3 * l)) & 7));
  return s;
}

void expect_error_falls(const PointNode& n, double error, double parent_error) {
  EXPECT_LT(error, parent_error);
  if (n.leaf()) {
    EXPECT_EQ(error, 0.0);
  } else {
    EXPECT_GT(error, 0.0);
  }
}

}  // namespace mv::test
