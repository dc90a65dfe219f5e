// 3D Tiles 1.1 point content: one binary glTF 2.0 (.glb) per tile holding a single POINTS primitive.
//   - POSITION: KHR_mesh_quantization, VEC3 UNSIGNED_SHORT *unnormalized* (stride 8), dequantized by the node:
//     tile frame = min + step * q, with one step for all three axes (step = largest extent / 65535). The
//     extension's own advice: unnormalized integers avoid the inexact 1/65535 factor and the signed-normalized
//     decoding differences between platforms; a uniform scale keeps the node a similarity. CesiumJS and
//     three.js (3d-tiles-renderer) read it. Error per axis at most step / 2 (0.76 mm for a 100 m tile).
//   - COLOR_0: VEC3 UNSIGNED_BYTE normalized (stride 4), when the points carry colours.
//   - Every PointProperty: one attribute "_" + upper-case name ("intensity" -> "_INTENSITY"), described by
//     EXT_structural_metadata (schema embedded, id "megavox_points", class "point", one property attribute)
//     under its own name, so a viewer finds "classification" by that name.
//   - The feature_id_property also becomes EXT_mesh_features' featureIds[0] ("attribute": 0, label = its
//     name): _FEATURE_ID_0 is the same accessor as the property's attribute.
//   - meshopt: every buffer view compressed with EXT_meshopt_compression (mode ATTRIBUTES, bitstream version
//     0, no filter); the uncompressed layout lives in a placeholder buffer marked "fallback", so the extension
//     is required. Without meshopt the views are plain and only KHR_mesh_quantization is required.
// glTF vertex attributes have no 32- or 64-bit integer or 64-bit float types, so (see PointProperty::Type):
//   - u8, i8, u16, i16 and f32 are stored as they are (UINT8, INT8, UINT16, INT16, FLOAT32);
//   - u32, i32 and f64 become FLOAT32 relative to the tile's minimum, the minimum (a JSON double, exact)
//     being the property attribute's `offset`: value = offset + stored. The class property says FLOAT32,
//     as EXT_structural_metadata requires of a property attribute. The error is half a float ulp of the
//     tile's span (max - min): exact for integer spans up to 2^24; for GPS time (f64 seconds) at most
//     0.48 us for spans under 16 s, 15 us under 512 s, 0.12 ms under 4096 s (68 min), 0.49 ms under 4.5 h.
//     A tile's points are near one another, so a span is the few seconds of one pass unless flight lines
//     cross it; microseconds over a whole flight would need two attributes per value, which no viewer
//     recombines.
// Both chunks end on 8-byte boundaries (EXT_structural_metadata asks it of GLB), so the binary chunk's data
// starts 8-aligned; every buffer view starts 4-aligned and every vertex stride is a multiple of 4.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace mv::io {

// One per-point attribute: `values` holds one little-endian value of `type` per point.
struct PointProperty {
  enum class Type : uint8_t { u8, i8, u16, i16, u32, i32, f32, f64 };
  std::string name;  // "intensity", "classification", "gps_time", "return_number", ...: [A-Za-z_][A-Za-z0-9_]*
  Type type = Type::u8;
  std::vector<uint8_t> values;
};

struct GlbPoints {
  std::vector<float> positions;  // 3 per point: metres in the tile's frame
  std::vector<uint8_t> rgb;      // 3 per point, or empty for none
  std::vector<PointProperty> properties;
  int feature_id_property = -1;  // index into `properties` (u8 or u16) whose values are the feature IDs, or -1
  // True: positions are in the tileset's z-up frame, and the node also rotates them into glTF's y-up frame,
  // which the y-up to z-up transform of every 3D Tiles runtime undoes. False: positions are glTF's own frame.
  bool rotate_z_up_to_y_up = true;
};

// The schema's id and class name, and the attribute name of a property ("gps_time" -> "_GPS_TIME").
inline constexpr const char* kGlbPointsSchemaId = "megavox_points";
inline constexpr const char* kGlbPointsClass = "point";
std::string glb_attribute_name(const std::string& property_name);

// Bytes of one value of `type`.
size_t point_property_size(PointProperty::Type type);

// The .glb of `points`, buffer views compressed with EXT_meshopt_compression when `meshopt`.
// Throws mv::Error when the sizes do not match the point count (3 positions, 3 colours or none, one value of
// its type per property), when there are no points, a position or float value is not finite, a name is not an
// identifier or repeats (also after upper-casing), feature_id_property is out of range or not u8/u16, or the
// file would exceed 4 GiB.
std::vector<uint8_t> encode_glb_points(const GlbPoints& points, bool meshopt);

}  // namespace mv::io
