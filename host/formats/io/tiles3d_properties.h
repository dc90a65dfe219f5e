// The per-point values a 3D Tiles tile carries besides position and colour: intensity, normals and every field
// of the point's attribute record (PointCloudInfo::fields), each under an identifier, as glb property attributes
// (3D Tiles 1.1) or batch table properties (1.0).
//
// What becomes a property, in this order:
//   - intensity (u16), when the cloud has it;
//   - normals as normal_x, normal_y, normal_z (f32), when it has them;
//   - each field of the record: its own type; a field with a scale or an offset (LAS extra bytes) as f64, the
//     quantity value * scale + add; a field of 2 or 3 values (LAS's vector extra bytes) as NAME_0, NAME_1, ...
// What is skipped, with the reason (written to the tileset's asset.extras):
//   - 64-bit integer fields: neither glTF vertex attributes nor the 1.0 batch table have a 64-bit integer type,
//     and a double would round values past 2^53;
//   - fields of more than 3 values (an untyped run of extra bytes): bytes, not a quantity a viewer can show;
//   - a record without fields (extra bytes nobody named).
// Names: characters outside [A-Za-z0-9_] become '_', a leading digit gets a '_' before it, and a name that
// repeats (also after upper-casing, as glb attribute names are) or is feature_id_0 gets _2, _3, ... The field
// named "classification" (u8 or u16, one value, unscaled) is the tile's feature ID (EXT_mesh_features).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "glb_points.h"
#include "megavox/points.h"

namespace mv::io {

struct TileProperty {
  enum class From : uint8_t { intensity, normal, field };
  std::string name;
  PointProperty::Type type = PointProperty::Type::u8;  // the type the tile stores
  From from = From::field;
  uint32_t offset = 0;  // normal: the axis; field: bytes into the attribute record (this value's)
  PointFieldType field_type = PointFieldType::u8;
  bool scaled = false;  // stored as f64: value * scale + add
  double scale = 1, add = 0;
};

struct TileSkipped {
  std::string name, reason;
};

struct TileProperties {
  std::vector<TileProperty> properties;
  int classification = -1;  // index of the property that is the feature ID, or -1
  std::vector<TileSkipped> skipped;
};

// The properties of `h`'s points. Throws mv::Error when a column or field does not fit the points held (a field
// beyond the record, an extra column of the wrong size).
TileProperties tile_properties(const PointHierarchy& h);

// The values of `p` for points [first, first + count) of `h`, one little-endian value of p.type each.
std::vector<uint8_t> tile_property_values(const PointHierarchy& h, const TileProperty& p, uint64_t first,
                                          uint64_t count);

}  // namespace mv::io
