#include "glb_points.h"

#include <meshoptimizer.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>

#include "megavox/error.h"

namespace mv::io {

// Values are copied as they lie in memory; glTF is little-endian.
static_assert(std::endian::native == std::endian::little);

namespace {

using ojson = nlohmann::ordered_json;  // keeps "asset" first and each object in the order the spec lists it

// glTF accessor.componentType and bufferView.target codes.
constexpr int kGlbByte = 5120;
constexpr int kGlbUnsignedByte = 5121;
constexpr int kGlbShort = 5122;
constexpr int kGlbUnsignedShort = 5123;
constexpr int kGlbFloat = 5126;
constexpr int kGlbArrayBuffer = 34962;
constexpr uint32_t kGlbQuantMax = 65535;  // largest UNSIGNED_SHORT position component

// One vertex attribute: its own buffer view of `count` elements, `stride` bytes each (a multiple of 4, as
// glTF asks of vertex attributes and EXT_meshopt_compression's ATTRIBUTES mode of its elements).
struct GlbStream {
  std::vector<uint8_t> bytes;
  uint32_t stride = 4;
  int component_type = kGlbUnsignedByte;
  const char* type = "SCALAR";
  bool normalized = false;
  ojson min, max;  // accessor.min / max, or null where glTF does not ask for them
};

// A property's class definition and its entry in the property attribute.
struct GlbPropertyJson {
  ojson class_property;
  ojson attribute_property;
};

template <class T>
T glb_load(const uint8_t* at) {
  T v;
  std::memcpy(&v, at, sizeof v);
  return v;
}

bool glb_identifier(const std::string& s) {  // ^[a-zA-Z_][a-zA-Z0-9_]*$, as the metadata spec requires
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
  return std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

const char* glb_type_name(PointProperty::Type t) {
  using T = PointProperty::Type;
  switch (t) {
    case T::u8: return "u8";
    case T::i8: return "i8";
    case T::u16: return "u16";
    case T::i16: return "i16";
    case T::u32: return "u32";
    case T::i32: return "i32";
    case T::f32: return "f32";
    case T::f64: return "f64";
  }
  return "?";
}

// u8, i8, u16, i16: the values as they are, each in a 4-byte slot; min and max are the raw values.
template <class T>
GlbStream glb_integer_stream(const PointProperty& p, size_t points, int component_type, const char* metadata_type,
                             GlbPropertyJson& js) {
  GlbStream s;
  s.component_type = component_type;
  s.bytes.assign(4 * points, 0);
  T lo = std::numeric_limits<T>::max(), hi = std::numeric_limits<T>::lowest();
  for (size_t i = 0; i < points; ++i) {
    const T v = glb_load<T>(p.values.data() + sizeof(T) * i);
    std::memcpy(s.bytes.data() + 4 * i, &v, sizeof v);
    lo = std::min(lo, v), hi = std::max(hi, v);
  }
  js.class_property = {{"type", "SCALAR"}, {"componentType", metadata_type}};
  js.attribute_property = {{"attribute", glb_attribute_name(p.name)}, {"min", lo}, {"max", hi}};
  return s;
}

// f32: stored as it is.
GlbStream glb_float_stream(const PointProperty& p, size_t points, GlbPropertyJson& js) {
  GlbStream s;
  s.component_type = kGlbFloat;
  s.bytes.assign(p.values.begin(), p.values.end());
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (size_t i = 0; i < points; ++i) {
    const float v = glb_load<float>(p.values.data() + 4 * i);
    if (!std::isfinite(v))
      throw Error("point property \"" + p.name + "\" holds a value that is not finite (point " + std::to_string(i) + ")");
    lo = std::min(lo, v), hi = std::max(hi, v);
  }
  js.class_property = {{"type", "SCALAR"}, {"componentType", "FLOAT32"}};
  js.attribute_property = {{"attribute", glb_attribute_name(p.name)}, {"min", lo}, {"max", hi}};
  return s;
}

// u32, i32, f64: FLOAT32 relative to the tile's minimum, which becomes the property attribute's `offset`
// (glb_points.h says why and how precise).
template <class T>
GlbStream glb_offset_float_stream(const PointProperty& p, size_t points, GlbPropertyJson& js) {
  std::vector<double> v(points);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (size_t i = 0; i < points; ++i) {
    v[i] = static_cast<double>(glb_load<T>(p.values.data() + sizeof(T) * i));
    if (!std::isfinite(v[i]))
      throw Error("point property \"" + p.name + "\" holds a value that is not finite (point " + std::to_string(i) + ")");
    lo = std::min(lo, v[i]), hi = std::max(hi, v[i]);
  }
  GlbStream s;
  s.component_type = kGlbFloat;
  s.bytes.resize(4 * points);
  float stored_max = 0;
  for (size_t i = 0; i < points; ++i) {
    const float f = static_cast<float>(v[i] - lo);
    std::memcpy(s.bytes.data() + 4 * i, &f, 4);
    stored_max = std::max(stored_max, f);
  }
  js.class_property = {{"type", "SCALAR"}, {"componentType", "FLOAT32"}};
  // min and max are the values after the transform, as a client computes them: offset + stored.
  js.attribute_property = {{"attribute", glb_attribute_name(p.name)},
                           {"offset", lo},
                           {"min", lo},
                           {"max", lo + static_cast<double>(stored_max)}};
  return s;
}

GlbStream glb_property_stream(const PointProperty& p, size_t points, GlbPropertyJson& js) {
  using T = PointProperty::Type;
  switch (p.type) {
    case T::u8: return glb_integer_stream<uint8_t>(p, points, kGlbUnsignedByte, "UINT8", js);
    case T::i8: return glb_integer_stream<int8_t>(p, points, kGlbByte, "INT8", js);
    case T::u16: return glb_integer_stream<uint16_t>(p, points, kGlbUnsignedShort, "UINT16", js);
    case T::i16: return glb_integer_stream<int16_t>(p, points, kGlbShort, "INT16", js);
    case T::u32: return glb_offset_float_stream<uint32_t>(p, points, js);
    case T::i32: return glb_offset_float_stream<int32_t>(p, points, js);
    case T::f32: return glb_float_stream(p, points, js);
    case T::f64: return glb_offset_float_stream<double>(p, points, js);
  }
  throw Error("point property \"" + p.name + "\" has an unknown type");
}

// Where the positions went: the quantized stream and the node that maps it back to the tile's frame.
struct GlbQuantized {
  GlbStream stream;
  double min[3] = {0, 0, 0};
  double step = 1;
};

// Positions as VEC3 UNSIGNED_SHORT (stride 8, the fourth slot zero): q = round((p - min) / step), one step
// for all axes so that the largest extent spans 0..65535. A single point, or points all in one place, get
// step 1 (any positive step dequantizes them exactly).
GlbQuantized glb_quantize_positions(const std::vector<float>& positions, size_t points) {
  GlbQuantized q;
  double hi[3];
  for (int a = 0; a < 3; ++a) q.min[a] = std::numeric_limits<double>::infinity(), hi[a] = -q.min[a];
  for (size_t i = 0; i < points; ++i)
    for (int a = 0; a < 3; ++a) {
      const float v = positions[3 * i + a];
      if (!std::isfinite(v)) throw Error("point " + std::to_string(i) + " of a glb tile has a position that is not finite");
      q.min[a] = std::min(q.min[a], double(v)), hi[a] = std::max(hi[a], double(v));
    }
  const double extent = std::max({hi[0] - q.min[0], hi[1] - q.min[1], hi[2] - q.min[2]});
  q.step = extent > 0 ? extent / kGlbQuantMax : 1.0;

  GlbStream& s = q.stream;
  s.stride = 8;
  s.component_type = kGlbUnsignedShort;
  s.type = "VEC3";
  s.bytes.assign(8 * points, 0);
  uint16_t qlo[3] = {UINT16_MAX, UINT16_MAX, UINT16_MAX}, qhi[3] = {0, 0, 0};
  for (size_t i = 0; i < points; ++i)
    for (int a = 0; a < 3; ++a) {
      const double r = std::round((double(positions[3 * i + a]) - q.min[a]) / q.step);
      const auto c = static_cast<uint16_t>(std::clamp(r, 0.0, double(kGlbQuantMax)));
      std::memcpy(s.bytes.data() + 8 * i + 2 * a, &c, 2);
      qlo[a] = std::min(qlo[a], c), qhi[a] = std::max(qhi[a], c);
    }
  // glTF requires POSITION's min and max, in the accessor's own (quantized) units.
  s.min = {qlo[0], qlo[1], qlo[2]};
  s.max = {qhi[0], qhi[1], qhi[2]};
  return q;
}

// Colours as VEC3 UNSIGNED_BYTE normalized, stride 4 (the fourth byte zero).
GlbStream glb_colour_stream(const std::vector<uint8_t>& rgb, size_t points) {
  GlbStream s;
  s.type = "VEC3";
  s.normalized = true;
  s.bytes.assign(4 * points, 0);
  for (size_t i = 0; i < points; ++i) std::memcpy(s.bytes.data() + 4 * i, rgb.data() + 3 * i, 3);
  return s;
}

// The number of distinct IDs (EXT_mesh_features' featureCount) among u8 or u16 values.
uint32_t glb_distinct_ids(const PointProperty& p, size_t points) {
  std::vector<bool> seen(65536, false);
  uint32_t distinct = 0;
  for (size_t i = 0; i < points; ++i) {
    const uint32_t id = p.type == PointProperty::Type::u8 ? p.values[i] : glb_load<uint16_t>(p.values.data() + 2 * i);
    if (!seen[id]) seen[id] = true, ++distinct;
  }
  return distinct;
}

// EXT_meshopt_compression ATTRIBUTES data of one stream, in bitstream version 0 (header 0xa0): the version the
// extension specifies, whatever a newer library would write by default.
std::vector<uint8_t> glb_meshopt_encode(const GlbStream& s, size_t points) {
  static const bool version_set = (meshopt_encodeVertexVersion(0), true);
  (void)version_set;
  std::vector<uint8_t> out(meshopt_encodeVertexBufferBound(points, s.stride));
  const size_t used = meshopt_encodeVertexBuffer(out.data(), out.size(), s.bytes.data(), points, s.stride);
  if (used == 0) throw Error("meshopt could not encode a vertex stream of " + std::to_string(points) + " points");
  out.resize(used);
  return out;
}

size_t glb_align(size_t n, size_t to) { return (n + to - 1) / to * to; }

void glb_put_u32(std::vector<uint8_t>& out, size_t at, uint32_t v) { std::memcpy(out.data() + at, &v, 4); }

void glb_check(const GlbPoints& g, size_t points) {
  if (g.positions.size() % 3 != 0)
    throw Error("a glb tile needs 3 position values per point; got " + std::to_string(g.positions.size()));
  if (points == 0) throw Error("a glb tile needs at least one point (glTF accessors hold one element or more)");
  if (!g.rgb.empty() && g.rgb.size() != 3 * points)
    throw Error("a glb tile of " + std::to_string(points) + " points needs " + std::to_string(3 * points) +
                " colour values or none; got " + std::to_string(g.rgb.size()));
  std::set<std::string> attributes = {"_FEATURE_ID_0"};
  for (const PointProperty& p : g.properties) {
    if (!glb_identifier(p.name))
      throw Error("point property name \"" + p.name + "\" is not an identifier ([A-Za-z_][A-Za-z0-9_]*)");
    if (!attributes.insert(glb_attribute_name(p.name)).second)
      throw Error("point property \"" + p.name + "\" would be attribute " + glb_attribute_name(p.name) +
                  ", which another property or the feature IDs already use");
    const size_t want = point_property_size(p.type) * points;
    if (p.values.size() != want)
      throw Error("point property \"" + p.name + "\" (" + glb_type_name(p.type) + ") needs " + std::to_string(want) +
                  " bytes for " + std::to_string(points) + " points; got " + std::to_string(p.values.size()));
  }
  if (g.feature_id_property < -1 || g.feature_id_property >= int(g.properties.size()))
    throw Error("feature_id_property " + std::to_string(g.feature_id_property) + " is not one of the " +
                std::to_string(g.properties.size()) + " point properties");
  if (g.feature_id_property >= 0) {
    const PointProperty& f = g.properties[g.feature_id_property];
    if (f.type != PointProperty::Type::u8 && f.type != PointProperty::Type::u16)
      throw Error("feature IDs (point property \"" + f.name + "\") must be u8 or u16; got " + glb_type_name(f.type));
  }
}

}  // namespace

size_t point_property_size(PointProperty::Type type) {
  using T = PointProperty::Type;
  switch (type) {
    case T::u8:
    case T::i8: return 1;
    case T::u16:
    case T::i16: return 2;
    case T::u32:
    case T::i32:
    case T::f32: return 4;
    case T::f64: return 8;
  }
  return 0;
}

std::string glb_attribute_name(const std::string& property_name) {
  std::string a = "_" + property_name;
  for (char& c : a) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return a;
}

std::vector<uint8_t> encode_glb_points(const GlbPoints& g, bool meshopt) {
  const size_t points = g.positions.size() / 3;
  glb_check(g, points);

  // The streams in accessor order: POSITION, COLOR_0, then the properties.
  std::vector<GlbStream> streams;
  std::vector<std::string> names;
  GlbQuantized quantized = glb_quantize_positions(g.positions, points);
  streams.push_back(std::move(quantized.stream));
  names.push_back("POSITION");
  if (!g.rgb.empty()) {
    streams.push_back(glb_colour_stream(g.rgb, points));
    names.push_back("COLOR_0");
  }
  ojson classes = ojson::object(), attribute_properties = ojson::object();
  for (const PointProperty& p : g.properties) {
    GlbPropertyJson js;
    streams.push_back(glb_property_stream(p, points, js));
    names.push_back(glb_attribute_name(p.name));
    classes[p.name] = std::move(js.class_property);
    attribute_properties[p.name] = std::move(js.attribute_property);
  }

  // Buffer views. Plain: each stream in buffer 0 (the BIN chunk). meshopt: the compressed streams in buffer 0,
  // the parent views in buffer 1, a placeholder with no data (the extension's "fallback" buffer).
  std::vector<uint8_t> bin;
  ojson buffer_views = ojson::array();
  size_t fallback_bytes = 0;
  for (const GlbStream& s : streams) {
    bin.resize(glb_align(bin.size(), 4), 0);
    ojson view = {{"buffer", meshopt ? 1 : 0},
                  {"byteOffset", meshopt ? fallback_bytes : bin.size()},
                  {"byteLength", s.bytes.size()},
                  {"byteStride", s.stride},
                  {"target", kGlbArrayBuffer}};
    if (meshopt) {
      const std::vector<uint8_t> packed = glb_meshopt_encode(s, points);
      view["extensions"]["EXT_meshopt_compression"] = {{"buffer", 0},
                                                       {"byteOffset", bin.size()},
                                                       {"byteLength", packed.size()},
                                                       {"byteStride", s.stride},
                                                       {"mode", "ATTRIBUTES"},
                                                       {"count", points}};
      bin.insert(bin.end(), packed.begin(), packed.end());
      fallback_bytes += s.bytes.size();  // a multiple of 4, as every stride is
    } else {
      bin.insert(bin.end(), s.bytes.begin(), s.bytes.end());
    }
    buffer_views.push_back(std::move(view));
  }

  ojson accessors = ojson::array(), attributes = ojson::object();
  for (size_t i = 0; i < streams.size(); ++i) {
    const GlbStream& s = streams[i];
    ojson a = {{"bufferView", i}, {"componentType", s.component_type}};
    if (s.normalized) a["normalized"] = true;
    a["count"] = points;
    a["type"] = s.type;
    if (!s.min.is_null()) a["min"] = s.min, a["max"] = s.max;
    accessors.push_back(std::move(a));
    attributes[names[i]] = i;
  }

  ojson extensions_used = {"KHR_mesh_quantization"};
  ojson extensions_required = {"KHR_mesh_quantization"};
  if (meshopt) {
    extensions_used.push_back("EXT_meshopt_compression");
    extensions_required.push_back("EXT_meshopt_compression");
  }
  ojson primitive = {{"attributes", attributes}, {"mode", 0}};
  ojson root_extensions = ojson::object();
  if (!g.properties.empty()) {
    extensions_used.push_back("EXT_structural_metadata");
    root_extensions["EXT_structural_metadata"] = {
        {"schema", {{"id", kGlbPointsSchemaId}, {"classes", {{kGlbPointsClass, {{"properties", classes}}}}}}},
        {"propertyAttributes", ojson::array({{{"class", kGlbPointsClass}, {"properties", attribute_properties}}})}};
    primitive["extensions"]["EXT_structural_metadata"] = {{"propertyAttributes", {0}}};
  }
  if (g.feature_id_property >= 0) {
    // _FEATURE_ID_0 names the property's own accessor: the same values, not stored twice.
    const PointProperty& f = g.properties[g.feature_id_property];
    const size_t accessor = (g.rgb.empty() ? 1 : 2) + size_t(g.feature_id_property);
    primitive["attributes"]["_FEATURE_ID_0"] = accessor;
    extensions_used.push_back("EXT_mesh_features");
    primitive["extensions"]["EXT_mesh_features"] = {
        {"featureIds", ojson::array({{{"featureCount", glb_distinct_ids(f, points)}, {"attribute", 0}, {"label", f.name}}})}};
  }

  // The node dequantizes: tile frame = min + step * q. With the z-up to y-up rotation R (-90 degrees about x,
  // (x, y, z) -> (x, z, -y)), glTF's T * R * S gives R * (min + step * q): the translation is R * min.
  ojson node = {{"mesh", 0}};
  const double* m = quantized.min;
  if (g.rotate_z_up_to_y_up) {
    node["translation"] = {m[0], m[2], -m[1]};
    node["rotation"] = {-std::sqrt(0.5), 0.0, 0.0, std::sqrt(0.5)};
  } else {
    node["translation"] = {m[0], m[1], m[2]};
  }
  node["scale"] = {quantized.step, quantized.step, quantized.step};

  // Buffer 0 is the whole BIN chunk, its zero padding included: validators warn when a chunk outgrows its
  // buffer by 4 bytes or more, which 8-byte padding would otherwise allow.
  bin.resize(glb_align(bin.size(), 8), 0);
  ojson buffers = ojson::array({{{"byteLength", bin.size()}}});
  if (meshopt)
    buffers.push_back({{"byteLength", fallback_bytes}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});

  ojson gltf = {{"asset", {{"version", "2.0"}, {"generator", "megavox"}}},
                {"extensionsUsed", extensions_used},
                {"extensionsRequired", extensions_required}};
  if (!root_extensions.empty()) gltf["extensions"] = root_extensions;
  gltf["scene"] = 0;
  gltf["scenes"] = ojson::array({{{"nodes", {0}}}});
  gltf["nodes"] = ojson::array({node});
  gltf["meshes"] = ojson::array({{{"primitives", ojson::array({primitive})}}});
  gltf["accessors"] = accessors;
  gltf["bufferViews"] = buffer_views;
  gltf["buffers"] = buffers;

  // GLB: a 12-byte header, the JSON chunk padded with spaces and the BIN chunk with zeros, each chunk ending on
  // an 8-byte boundary of the file (so the BIN data starts 8-aligned, as EXT_structural_metadata asks).
  constexpr size_t kHeader = 12, kChunkHeader = 8;
  std::string json = gltf.dump();
  json.resize(glb_align(kHeader + kChunkHeader + json.size(), 8) - kHeader - kChunkHeader, ' ');
  const size_t bin_chunk = bin.size();  // already a multiple of 8
  const size_t total = kHeader + kChunkHeader + json.size() + kChunkHeader + bin_chunk;
  if (total > UINT32_MAX || fallback_bytes > UINT32_MAX)
    throw Error("a glb tile of " + std::to_string(points) + " points exceeds 4 GiB");

  std::vector<uint8_t> out(total, 0);
  std::memcpy(out.data(), "glTF", 4);
  glb_put_u32(out, 4, 2);  // GLB version
  glb_put_u32(out, 8, static_cast<uint32_t>(total));
  glb_put_u32(out, 12, static_cast<uint32_t>(json.size()));
  std::memcpy(out.data() + 16, "JSON", 4);
  std::memcpy(out.data() + 20, json.data(), json.size());
  const size_t bin_at = kHeader + kChunkHeader + json.size();
  glb_put_u32(out, bin_at, static_cast<uint32_t>(bin_chunk));
  std::memcpy(out.data() + bin_at + 4, "BIN\0", 4);
  if (!bin.empty()) std::memcpy(out.data() + bin_at + kChunkHeader, bin.data(), bin.size());
  return out;
}

}  // namespace mv::io
