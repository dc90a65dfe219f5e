// Small point hierarchies made by hand for the 3D Tiles tests: a plain octree over clustered points (split
// where a node holds more than `capacity`, every k-th point of an inner node's subtree as its
// representatives), laid out as points.h says. Not the project's LOD builder: only its output's shape.
// With `fields`, every point carries intensity and an attribute record of kSyntheticRecordBytes that
// synthetic_fields() lays out: LAS-like fields (classification, gps_time, ...) and the cases a tile writer must
// decide on (a 64-bit integer, a scaled value, a 3-vector, an untyped run of bytes, names to be made identifiers).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "io/tiles3d_writer.h"
#include "megavox/points.h"

namespace mv::test {

enum class Colour { none, bits8, bits16 };

struct SyntheticCloud {
  uint32_t points = 5000;
  uint32_t capacity = 200;
  uint32_t max_level = 8;
  uint32_t shift = 1;
  Colour colour = Colour::bits16;
  bool z_up = true;
  std::string crs = "EPSG:32633";
  uint64_t seed = 7;
  bool fields = false;
};

inline constexpr uint32_t kSyntheticRecordBytes = 38;
std::vector<PointField> synthetic_fields();

PointHierarchy synthetic_hierarchy(const SyntheticCloud& c);

// What a tile writer should make of a synthetic cloud's columns (tiles3d_properties.h's rules, spelled out by
// hand): the properties in order, each read from the hierarchy by the test's own decoding; and the fields skipped.
struct SyntheticProperty {
  std::string name;
  int field = -1;          // index into h.source.fields; -1: intensity
  uint32_t component = 0;  // the value within the field
  bool exact_in_glb = true;  // false: glb carries it as float relative to the tile's minimum
};
std::vector<SyntheticProperty> synthetic_properties(const PointHierarchy& h);
std::vector<std::string> synthetic_skipped(const PointHierarchy& h);
// Stored point `point`'s value of `p` (value * scale + add for a scaled field).
double synthetic_value(const PointHierarchy& h, const SyntheticProperty& p, uint64_t point);

// 3D Tiles 1.0 in the input's own CRS (the writer's options).
inline const io::Tiles3dOptions kTiles10{0, "", true};

// A node's tile name: "r", then one octant digit per level ("r07").
std::string tile_name(uint64_t code, uint32_t level);
// A tile's geometric error against its parent's: always falling, 0 exactly at the leaves (gtest expectations).
void expect_error_falls(const PointNode& n, double error, double parent_error);

}  // namespace mv::test
