// megavox — point clouds: the columns a reader delivers and the LOD hierarchy the builder makes of them.
//
// Positions are integers on the input's own grid (docs/points.md): world = offset + scale * xyz per
// axis, in double. A LAS file's grid is its header's scale and offset; a float PLY's is chosen from the data's
// precision (io/point_source.h). Attributes travel with their point as parallel columns.
// No device types: readers and reference code use these alone.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace mv {

// Optional attribute columns, as bits of PointCloudInfo::attributes.
enum PointAttribute : uint32_t {
  kPointRgb = 1,        // 3 x uint16 per point, as stored (LAS: 16-bit fields, PLY: uchar or ushort)
  kPointNormal = 2,     // 3 x float per point
  kPointIntensity = 4,  // 1 x uint16 per point
  kPointExtra = 8,      // PointCloudInfo::extra_bytes bytes per point: the attribute record PointCloudInfo::fields lays out
};

// The type of one value of a PointField.
enum class PointFieldType : uint8_t { u8, i8, u16, i16, u32, i32, u64, i64, f32, f64 };

// Bytes of one value of `t`.
inline uint32_t point_field_size(PointFieldType t) {
  constexpr uint8_t kSize[] = {1, 1, 2, 2, 4, 4, 8, 8, 4, 8};
  return kSize[static_cast<int>(t)];
}
// "u8", "f64", ...: the name .mvx and the docs use.
inline const char* point_field_type_name(PointFieldType t) {
  constexpr const char* kName[] = {"u8", "i8", "u16", "i16", "u32", "i32", "u64", "i64", "f32", "f64"};
  return kName[static_cast<int>(t)];
}

// A named per-point value inside the attribute record (PointColumns::extra): LAS's fields beyond position,
// intensity and colour (return_number, number_of_returns, classification, classification_flags,
// scanner_channel, scan_direction_flag, edge_of_flight_line, user_data, scan_angle, point_source_id, gps_time,
// nir) and the extra bytes its Extra Bytes records describe. Values are little-endian, unaligned.
struct PointField {
  std::string name;
  PointFieldType type = PointFieldType::u8;
  uint32_t offset = 0;  // bytes into the point's record
  uint32_t count = 1;   // values (an untyped run of extra bytes: count bytes)
  double scale = 1, add = 0;  // the quantity is value * scale + add (LAS extra bytes' scale and offset)
  std::string description;
  bool operator==(const PointField&) const = default;
};

// Points as columns (struct of arrays). A column an info's attributes do not name is empty.
struct PointColumns {
  std::vector<int32_t> xyz;         // 3 per point
  std::vector<uint16_t> rgb;        // 3 per point
  std::vector<float> normal;        // 3 per point
  std::vector<uint16_t> intensity;  // 1 per point
  std::vector<uint8_t> extra;       // extra_bytes per point: the attribute record (PointCloudInfo::fields)

  uint64_t size() const { return xyz.size() / 3; }
  void clear();
  // Room for `more` points beyond size() in the columns `attributes` names, growing capacity at least
  // geometrically: readers append batch after batch, and an exact reserve per batch would copy the columns
  // each time.
  void reserve_more(uint64_t more, uint32_t attributes, uint32_t extra_bytes);
  // Appends point i of `from` (which carries the same columns, with `extra_bytes` bytes of extra per point).
  void append(const PointColumns& from, uint64_t i, uint32_t extra_bytes);
};

struct PointCloudInfo {
  std::string format;         // what was read, for messages and `points info`: "LAS 1.2, point format 3", ...
  uint64_t points = 0;        // declared by the header
  uint32_t attributes = 0;    // PointAttribute bits
  uint32_t extra_bytes = 0;   // per point, with kPointExtra
  std::vector<PointField> fields;  // what the extra bytes hold, in offset order (may be empty: bytes unnamed)
  double scale[3] = {1, 1, 1};
  double offset[3] = {0, 0, 0};
  bool z_up = false;          // LAS: +Z up; PLY: +Y up (the render's camera presets)
  std::string crs;            // the CRS the input declared (LAS WKT), or empty
};

// A cloud in the caller's memory (the C API's build from arrays): world positions as float or double (exactly
// one of xyz32 and xyz64, 3 per point), and optional columns as PointColumns holds them.
struct PointArrays {
  std::span<const float> xyz32;
  std::span<const double> xyz64;
  std::span<const uint16_t> rgb, intensity;
  std::span<const uint8_t> extra;
  uint32_t extra_bytes = 0;
};

// One node of the LOD octree. Codes carry a sentinel bit above 3 * level Morton bits (OMiCroN's convention):
// the root is 1, a child of c is (c << 3) | octant, the level is (bit width of code - 1) / 3.
// The octant is x + 2y + 4z, each bit the upper (1) or lower (0) half of the parent's cube on that axis (x
// lowest, as kernels/common/morton.h): a node's cube is its code's Morton bits read as a cell at its level
// (the 3D Tiles writer relies on it).
struct PointNode {
  uint64_t code = 1;
  uint64_t first_point = 0;      // into PointHierarchy::points
  uint64_t subtree_points = 0;   // input points at the leaves of its subtree
  uint32_t point_count = 0;      // a leaf: all of its points; an inner node: its representatives
  uint32_t first_child = 0;      // index of its first child in PointHierarchy::nodes (children are contiguous)
  uint8_t child_mask = 0;        // bit o: a child in octant o; 0 for a leaf
  uint8_t level = 0;
  uint16_t pad = 0;
  uint32_t reserved = 0;         // makes the 40 bytes .mvx stores explicit (no padding of unknown value)
  bool leaf() const { return child_mask == 0; }
};

// The finished hierarchy: nodes breadth-first (root first, each node's children contiguous and in octant
// order), points in node order (node i's points are points[first_point, first_point + point_count)).
struct PointHierarchy {
  PointCloudInfo source;
  // The cube the Morton codes cover, on the input's grid: a point's 21-bit cell per axis is
  // (xyz - cube_min) >> shift (a negative shift scales up: << -shift, for clouds spanning fewer than 2^21
  // units), so the cube's side is 2^(21 + shift) input units.
  int64_t cube_min[3] = {0, 0, 0};
  int32_t shift = 0;
  uint32_t depth = 0;      // the deepest level that holds a node
  uint32_t grid_bits = 6;  // an inner node at level l keeps one point per cell of level l + grid_bits
  std::vector<PointNode> nodes;
  PointColumns points;
  uint64_t points_in = 0;       // read from the input
  uint64_t points_kept = 0;     // at the leaves (points_in - points_dropped)
  uint64_t points_dropped = 0;  // counted, with the reason in the build's report
  std::vector<uint64_t> nodes_per_level;  // index = level

  // Point p's cell along `axis`.
  uint32_t cell(uint64_t p, int axis) const {
    const uint64_t d = static_cast<uint64_t>(int64_t{points.xyz[3 * p + axis]} - cube_min[axis]);
    return static_cast<uint32_t>(shift >= 0 ? d >> shift : d << -shift);
  }
};

}  // namespace mv
