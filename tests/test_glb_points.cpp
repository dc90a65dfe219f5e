// Glb point tiles (io/glb_points.h) read back by hand: the GLB container, the glTF accessor and buffer-view
// rules, the extensions declared, the metadata schema and feature IDs, and every value decoded (meshopt views
// with meshoptimizer's own decoder) against the input: positions within half a quantization step, the rest
// exact or, for values carried as float relative to an offset, within half a float ulp of their span.
#include <meshoptimizer.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <set>

#include "io/glb_points.h"
#include "test_support.h"

namespace mv::test {
namespace {

using nlohmann::json;
using io::GlbPoints;
using io::PointProperty;

uint32_t glbt_u32(const std::vector<uint8_t>& b, size_t at) {
  uint32_t v;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

template <class T>
void glbt_append(PointProperty& p, T v) {
  uint8_t b[sizeof(T)];
  std::memcpy(b, &v, sizeof v);
  p.values.insert(p.values.end(), b, b + sizeof v);
}

template <class T>
T glbt_value(const std::vector<uint8_t>& bytes, size_t at) {
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof v);
  return v;
}

// The file's JSON and BIN chunk, after checking the container: magic, version, length, chunk types, both
// chunks ending on 8-byte boundaries, buffer 0 within the BIN chunk.
struct GlbtFile {
  json gltf;
  std::vector<uint8_t> bin;
};

void glbt_read(const std::vector<uint8_t>& f, GlbtFile& out) {
  ASSERT_GE(f.size(), 28u);
  EXPECT_EQ(std::memcmp(f.data(), "glTF", 4), 0);
  EXPECT_EQ(glbt_u32(f, 4), 2u);
  ASSERT_EQ(glbt_u32(f, 8), f.size());
  const uint32_t json_len = glbt_u32(f, 12);
  EXPECT_EQ(std::memcmp(f.data() + 16, "JSON", 4), 0);
  EXPECT_EQ((20 + json_len) % 8, 0u) << "the JSON chunk ends on an 8-byte boundary";
  ASSERT_LE(28 + size_t(json_len), f.size());
  out.gltf = json::parse(f.begin() + 20, f.begin() + 20 + json_len);
  const size_t bin_at = 20 + json_len;
  const uint32_t bin_len = glbt_u32(f, bin_at);
  EXPECT_EQ(std::memcmp(f.data() + bin_at + 4, "BIN\0", 4), 0);
  EXPECT_EQ(bin_len % 8, 0u);
  ASSERT_EQ(bin_at + 8 + bin_len, f.size());
  out.bin.assign(f.begin() + bin_at + 8, f.end());
  const size_t buffer0 = out.gltf.at("buffers").at(0).at("byteLength");
  EXPECT_LE(buffer0, out.bin.size());
  EXPECT_GT(buffer0 + 8, out.bin.size()) << "at most 7 bytes of padding";
}

// The decoded bytes of buffer view `v` (count * stride), checking its layout rules on the way; meshopt views
// decoded with meshopt_decodeVertexBuffer.
void glbt_view(const GlbtFile& g, size_t v, size_t count, std::vector<uint8_t>& out) {
  const json& view = g.gltf.at("bufferViews").at(v);
  const size_t stride = view.at("byteStride"), length = view.at("byteLength");
  const size_t offset = view.value("byteOffset", size_t{0});
  EXPECT_EQ(stride % 4, 0u);
  EXPECT_GE(stride, 4u);
  EXPECT_LE(stride, 252u);
  EXPECT_EQ(offset % 4, 0u);
  EXPECT_EQ(length, stride * count);
  EXPECT_EQ(view.at("target"), 34962);
  out.assign(length, 0);
  if (!view.contains("extensions")) {
    ASSERT_EQ(view.at("buffer"), 0);
    ASSERT_LE(offset + length, size_t(g.gltf["buffers"][0]["byteLength"]));
    std::memcpy(out.data(), g.bin.data() + offset, length);
    return;
  }
  const json& m = view.at("extensions").at("EXT_meshopt_compression");
  const json& parent_buffer = g.gltf.at("buffers").at(size_t(view.at("buffer")));
  EXPECT_EQ(parent_buffer.at("extensions").at("EXT_meshopt_compression").at("fallback"), true);
  EXPECT_FALSE(parent_buffer.contains("uri"));
  EXPECT_LE(offset + length, size_t(parent_buffer.at("byteLength")));
  ASSERT_EQ(m.at("buffer"), 0) << "compressed data lies in the BIN chunk";
  EXPECT_EQ(m.at("mode"), "ATTRIBUTES");
  EXPECT_EQ(m.value("filter", std::string("NONE")), "NONE");
  EXPECT_EQ(m.at("byteStride"), stride);
  EXPECT_EQ(m.at("count"), count);
  const size_t at = m.value("byteOffset", size_t{0}), packed = m.at("byteLength");
  EXPECT_EQ(at % 4, 0u);
  ASSERT_LE(at + packed, size_t(g.gltf["buffers"][0]["byteLength"]));
  EXPECT_EQ(g.bin[at], 0xa0) << "attribute bitstream version 0, the one EXT_meshopt_compression specifies";
  ASSERT_EQ(meshopt_decodeVertexBuffer(out.data(), count, stride, g.bin.data() + at, packed), 0);
}

// Rotates v by the unit quaternion q = (x, y, z, w).
void glbt_rotate(const double q[4], double v[3]) {
  const double u[3] = {q[0], q[1], q[2]}, w = q[3];
  const double t[3] = {2 * (u[1] * v[2] - u[2] * v[1]), 2 * (u[2] * v[0] - u[0] * v[2]), 2 * (u[0] * v[1] - u[1] * v[0])};
  const double r[3] = {v[0] + w * t[0] + u[1] * t[2] - u[2] * t[1], v[1] + w * t[1] + u[2] * t[0] - u[0] * t[2],
                       v[2] + w * t[2] + u[0] * t[1] - u[1] * t[0]};
  for (int a = 0; a < 3; ++a) v[a] = r[a];
}

// A cloud on a random walk: rgb, intensity (u16), classification (u8, the feature IDs), gps_time (f64, an
// hour of flight), return_number (u8).
GlbPoints glbt_walk(size_t points, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> step(0.f, 0.05f);
  std::uniform_int_distribution<int> byte(0, 255);
  GlbPoints g;
  PointProperty intensity{"intensity", PointProperty::Type::u16, {}};
  PointProperty classification{"classification", PointProperty::Type::u8, {}};
  PointProperty gps_time{"gps_time", PointProperty::Type::f64, {}};
  PointProperty return_number{"return_number", PointProperty::Type::u8, {}};
  float p[3] = {120.5f, -30.25f, 8.f};
  uint8_t cls = 2;
  for (size_t i = 0; i < points; ++i) {
    for (int a = 0; a < 3; ++a) p[a] += step(rng), g.positions.push_back(p[a]);
    for (int c = 0; c < 3; ++c) g.rgb.push_back(uint8_t(byte(rng)));
    glbt_append<uint16_t>(intensity, uint16_t(byte(rng) * 200));
    if (byte(rng) < 10) cls = uint8_t(byte(rng) % 12);
    glbt_append<uint8_t>(classification, cls);
    glbt_append<double>(gps_time, 318'123'456.789012 + 3600.0 * double(i) / double(points) + 1e-6 * (i % 7));
    glbt_append<uint8_t>(return_number, uint8_t(1 + byte(rng) % 4));
  }
  g.properties = {intensity, classification, gps_time, return_number};
  g.feature_id_property = 1;
  return g;
}

// Checks `file` against `g` in full: JSON structure, extensions, schema, and every decoded value.
void glbt_check(const std::vector<uint8_t>& file, const GlbPoints& g, bool meshopt) {
  GlbtFile f;
  ASSERT_NO_FATAL_FAILURE(glbt_read(file, f));
  const json& j = f.gltf;
  const size_t n = g.positions.size() / 3;
  EXPECT_EQ(j.at("asset").at("version"), "2.0");

  std::set<std::string> used = j.at("extensionsUsed"), required = j.at("extensionsRequired");
  std::set<std::string> want_used = {"KHR_mesh_quantization"}, want_required = {"KHR_mesh_quantization"};
  if (meshopt) want_used.insert("EXT_meshopt_compression"), want_required.insert("EXT_meshopt_compression");
  if (!g.properties.empty()) want_used.insert("EXT_structural_metadata");
  if (g.feature_id_property >= 0) want_used.insert("EXT_mesh_features");
  EXPECT_EQ(used, want_used);
  EXPECT_EQ(required, want_required);
  EXPECT_EQ(j.at("buffers").size(), meshopt ? 2u : 1u);

  ASSERT_EQ(j.at("meshes").size(), 1u);
  ASSERT_EQ(j.at("meshes")[0].at("primitives").size(), 1u);
  const json& prim = j["meshes"][0]["primitives"][0];
  EXPECT_EQ(prim.at("mode"), 0);
  EXPECT_FALSE(prim.contains("indices"));
  const json& attrs = prim.at("attributes");
  EXPECT_EQ(attrs.size(), 1 + !g.rgb.empty() + g.properties.size() + (g.feature_id_property >= 0));
  for (const auto& [name, index] : attrs.items())
    EXPECT_TRUE(name == "POSITION" || name == "COLOR_0" || name[0] == '_') << name << ": custom attributes start with _";

  auto accessor_bytes = [&](const std::string& attribute, int component_type, const char* type, bool normalized,
                            std::vector<uint8_t>& bytes, size_t& stride) {
    SCOPED_TRACE(attribute);
    ASSERT_TRUE(attrs.contains(attribute));
    const json& a = j.at("accessors").at(size_t(attrs[attribute]));
    EXPECT_EQ(a.at("componentType"), component_type);
    EXPECT_EQ(a.at("type"), type);
    EXPECT_EQ(a.value("normalized", false), normalized);
    EXPECT_EQ(a.at("count"), n);
    EXPECT_EQ(a.value("byteOffset", 0), 0);
    const size_t v = a.at("bufferView");
    stride = j["bufferViews"][v].at("byteStride");
    ASSERT_NO_FATAL_FAILURE(glbt_view(f, v, n, bytes));
  };

  // POSITION: quantized, min/max exact, dequantized by the node within half a step.
  std::vector<uint8_t> bytes;
  size_t stride = 0;
  ASSERT_NO_FATAL_FAILURE(accessor_bytes("POSITION", 5123, "VEC3", false, bytes, stride));
  const json& pa = j["accessors"][size_t(attrs["POSITION"])];
  const json& node = j.at("nodes").at(0);
  EXPECT_EQ(j.at("scenes")[0].at("nodes"), json::array({0}));
  EXPECT_EQ(node.at("mesh"), 0);
  const double s = node.at("scale")[0];
  EXPECT_EQ(node["scale"][1], s);
  EXPECT_EQ(node["scale"][2], s) << "one step for all axes";
  double q[4] = {0, 0, 0, 1};
  if (g.rotate_z_up_to_y_up) {
    for (int k = 0; k < 4; ++k) q[k] = node.at("rotation")[k];
    EXPECT_NEAR(q[0], -std::sqrt(0.5), 1e-15);
    EXPECT_NEAR(q[3], std::sqrt(0.5), 1e-15);
  } else {
    EXPECT_FALSE(node.contains("rotation"));
  }
  uint16_t lo[3] = {65535, 65535, 65535}, hi[3] = {0, 0, 0};
  double worst = 0;
  for (size_t i = 0; i < n; ++i) {
    double p[3];
    for (int a = 0; a < 3; ++a) {
      const uint16_t c = glbt_value<uint16_t>(bytes, stride * i + 2 * a);
      lo[a] = std::min(lo[a], c), hi[a] = std::max(hi[a], c);
      p[a] = s * c;
    }
    glbt_rotate(q, p);  // glTF's node: T * R * S
    for (int a = 0; a < 3; ++a) p[a] += double(node.at("translation")[a]);
    if (g.rotate_z_up_to_y_up) {  // 3D Tiles' y-up to z-up: (x, y, z) -> (x, -z, y)
      const double y = p[1];
      p[1] = -p[2], p[2] = y;
    }
    for (int a = 0; a < 3; ++a) worst = std::max(worst, std::abs(p[a] - double(g.positions[3 * i + a])));
  }
  EXPECT_LE(worst, s / 2 * (1 + 1e-6) + 1e-9) << "step " << s;
  if (std::max({hi[0], hi[1], hi[2]}) > 0) {
    EXPECT_EQ(std::max({hi[0], hi[1], hi[2]}), 65535) << "the largest extent spans the whole 16 bits";
  }
  for (int a = 0; a < 3; ++a) {
    EXPECT_EQ(pa.at("min")[a], lo[a]);
    EXPECT_EQ(pa.at("max")[a], hi[a]);
  }

  if (!g.rgb.empty()) {
    ASSERT_NO_FATAL_FAILURE(accessor_bytes("COLOR_0", 5121, "VEC3", true, bytes, stride));
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(bytes[stride * i + c], g.rgb[3 * i + c]) << "point " << i;
  } else {
    EXPECT_FALSE(attrs.contains("COLOR_0"));
  }

  if (g.properties.empty()) {
    EXPECT_FALSE(j.contains("extensions"));
    return;
  }
  const json& meta = j.at("extensions").at("EXT_structural_metadata");
  EXPECT_EQ(meta.at("schema").at("id"), io::kGlbPointsSchemaId);
  const json& cls = meta["schema"].at("classes").at(io::kGlbPointsClass).at("properties");
  ASSERT_EQ(meta.at("propertyAttributes").size(), 1u);
  const json& pattr = meta["propertyAttributes"][0];
  EXPECT_EQ(pattr.at("class"), io::kGlbPointsClass);
  EXPECT_EQ(prim.at("extensions").at("EXT_structural_metadata").at("propertyAttributes"), json::array({0}));
  EXPECT_EQ(cls.size(), g.properties.size());
  for (const PointProperty& p : g.properties) {
    SCOPED_TRACE(p.name);
    const std::string attribute = io::glb_attribute_name(p.name);
    ASSERT_TRUE(cls.contains(p.name));
    EXPECT_EQ(cls[p.name].at("type"), "SCALAR");
    const json& pp = pattr.at("properties").at(p.name);
    EXPECT_EQ(pp.at("attribute"), attribute);
    using T = PointProperty::Type;
    static const std::map<T, std::pair<int, std::string>> kinds = {
        {T::u8, {5121, "UINT8"}},   {T::i8, {5120, "INT8"}},     {T::u16, {5123, "UINT16"}},
        {T::i16, {5122, "INT16"}},  {T::u32, {5126, "FLOAT32"}}, {T::i32, {5126, "FLOAT32"}},
        {T::f32, {5126, "FLOAT32"}}, {T::f64, {5126, "FLOAT32"}}};
    const auto& [component_type, metadata_type] = kinds.at(p.type);
    EXPECT_EQ(cls[p.name].at("componentType"), metadata_type);
    ASSERT_NO_FATAL_FAILURE(accessor_bytes(attribute, component_type, "SCALAR", false, bytes, stride));
    const bool offset = p.type == T::u32 || p.type == T::i32 || p.type == T::f64;
    EXPECT_EQ(pp.contains("offset"), offset);
    double span = 0, lo_v = INFINITY, hi_v = -INFINITY;
    auto input = [&](size_t i) -> double {
      switch (p.type) {
        case T::u8: return glbt_value<uint8_t>(p.values, i);
        case T::i8: return glbt_value<int8_t>(p.values, i);
        case T::u16: return glbt_value<uint16_t>(p.values, 2 * i);
        case T::i16: return glbt_value<int16_t>(p.values, 2 * i);
        case T::u32: return glbt_value<uint32_t>(p.values, 4 * i);
        case T::i32: return glbt_value<int32_t>(p.values, 4 * i);
        case T::f32: return glbt_value<float>(p.values, 4 * i);
        case T::f64: return glbt_value<double>(p.values, 8 * i);
      }
      return NAN;
    };
    for (size_t i = 0; i < n; ++i) lo_v = std::min(lo_v, input(i)), hi_v = std::max(hi_v, input(i));
    span = hi_v - lo_v;
    // Half a float ulp of the span: the precision glb_points.h promises for offset values.
    const double tolerance = offset ? std::ldexp(1.0, std::ilogb(std::max(span, 1e-300)) - 24) : 0.0;
    const double base = offset ? double(pp["offset"]) : 0.0;
    if (offset) {
      EXPECT_EQ(base, lo_v);
    }
    double worst_value = 0;
    for (size_t i = 0; i < n; ++i) {
      double got = 0;
      switch (component_type) {
        case 5121: got = glbt_value<uint8_t>(bytes, stride * i); break;
        case 5120: got = glbt_value<int8_t>(bytes, stride * i); break;
        case 5123: got = glbt_value<uint16_t>(bytes, stride * i); break;
        case 5122: got = glbt_value<int16_t>(bytes, stride * i); break;
        default: got = glbt_value<float>(bytes, stride * i);
      }
      worst_value = std::max(worst_value, std::abs(base + got - input(i)));
    }
    EXPECT_LE(worst_value, tolerance);
    EXPECT_NEAR(double(pp.at("min")), lo_v, tolerance);
    EXPECT_NEAR(double(pp.at("max")), hi_v, tolerance);
  }

  if (g.feature_id_property < 0) {
    EXPECT_FALSE(prim["extensions"].contains("EXT_mesh_features"));
    return;
  }
  const PointProperty& fp = g.properties[g.feature_id_property];
  const json& ids = prim["extensions"].at("EXT_mesh_features").at("featureIds");
  ASSERT_EQ(ids.size(), 1u);
  EXPECT_EQ(ids[0].at("attribute"), 0);
  EXPECT_EQ(ids[0].at("label"), fp.name);
  EXPECT_EQ(attrs.at("_FEATURE_ID_0"), attrs.at(io::glb_attribute_name(fp.name))) << "one accessor for both";
  const json& fa = j["accessors"][size_t(attrs["_FEATURE_ID_0"])];
  EXPECT_EQ(fa.at("type"), "SCALAR");
  EXPECT_FALSE(fa.value("normalized", false));
  std::set<uint32_t> distinct;
  for (size_t i = 0; i < n; ++i)
    distinct.insert(fp.type == PointProperty::Type::u8 ? fp.values[i] : glbt_value<uint16_t>(fp.values, 2 * i));
  EXPECT_EQ(ids[0].at("featureCount"), distinct.size());
}

TEST(GlbPoints, PlainWalkReadsBack) {
  const GlbPoints g = glbt_walk(10000, 3);
  glbt_check(io::encode_glb_points(g, false), g, false);
}

TEST(GlbPoints, MeshoptWalkReadsBackAndIsSmaller) {
  const GlbPoints g = glbt_walk(10000, 3);
  const std::vector<uint8_t> packed = io::encode_glb_points(g, true), plain = io::encode_glb_points(g, false);
  glbt_check(packed, g, true);
  EXPECT_LT(packed.size(), plain.size() / 2) << packed.size() << " vs " << plain.size();
  // The decoded meshopt views are the plain views, byte for byte.
  GlbtFile a, b;
  glbt_read(packed, a);
  glbt_read(plain, b);
  ASSERT_EQ(a.gltf["bufferViews"].size(), b.gltf["bufferViews"].size());
  for (size_t v = 0; v < a.gltf["bufferViews"].size(); ++v) {
    std::vector<uint8_t> va, vb;
    glbt_view(a, v, 10000, va);
    glbt_view(b, v, 10000, vb);
    EXPECT_EQ(va, vb) << "view " << v;
  }
}

// Every property type, no colours, glTF's own frame; values at the types' limits.
TEST(GlbPoints, EveryPropertyType) {
  GlbPoints g;
  g.rotate_z_up_to_y_up = false;
  using T = PointProperty::Type;
  std::vector<PointProperty> props = {{"u8v", T::u8, {}},   {"i8v", T::i8, {}},   {"u16v", T::u16, {}},
                                      {"i16v", T::i16, {}}, {"u32v", T::u32, {}}, {"i32v", T::i32, {}},
                                      {"f32v", T::f32, {}}, {"f64v", T::f64, {}}};
  const size_t n = 300;
  for (size_t i = 0; i < n; ++i) {
    g.positions.insert(g.positions.end(), {float(i) * 0.01f, 5.f - float(i % 17), -1000.f + float(i % 5) * 0.001f});
    glbt_append<uint8_t>(props[0], uint8_t(i == 0 ? 255 : i % 7));
    glbt_append<int8_t>(props[1], int8_t(i == 0 ? -128 : int(i % 9) - 4));
    glbt_append<uint16_t>(props[2], uint16_t(i == 1 ? 65535 : i));
    glbt_append<int16_t>(props[3], int16_t(i == 1 ? -32768 : int(i) - 100));
    glbt_append<uint32_t>(props[4], uint32_t(4'000'000'000u + i * 50'000u));  // span 15e6 < 2^24: exact
    glbt_append<int32_t>(props[5], int32_t(-2'000'000'000 + int(i) * 3));
    glbt_append<float>(props[6], -1.5e30f + float(i));
    glbt_append<double>(props[7], 1e12 + 0.25 * double(i));
  }
  g.properties = props;
  g.feature_id_property = 2;  // u16 IDs
  for (bool meshopt : {false, true}) {
    SCOPED_TRACE(meshopt ? "meshopt" : "plain");
    glbt_check(io::encode_glb_points(g, meshopt), g, meshopt);
  }
}

// Positions only; a single point (step 1, exact); points all in one place.
TEST(GlbPoints, PositionsOnlyAndDegenerate) {
  for (size_t n : {1, 50}) {
    GlbPoints g;
    for (size_t i = 0; i < n; ++i) g.positions.insert(g.positions.end(), {3.25f, -7.5f, 1e5f});
    for (bool meshopt : {false, true}) {
      SCOPED_TRACE(std::to_string(n) + (meshopt ? " meshopt" : " plain"));
      const std::vector<uint8_t> file = io::encode_glb_points(g, meshopt);
      glbt_check(file, g, meshopt);
      GlbtFile f;
      glbt_read(file, f);
      EXPECT_EQ(f.gltf["nodes"][0]["scale"][0], 1.0);
    }
  }
}

TEST(GlbPoints, InconsistentInputIsRefused) {
  const GlbPoints good = glbt_walk(20, 5);
  auto refused = [&](const char* what, auto change, const std::string& says) {
    GlbPoints g = good;
    change(g);
    EXPECT_NE(error_message([&] { io::encode_glb_points(g, true); }).find(says), std::string::npos) << what;
  };
  refused("no points", [](GlbPoints& g) { g = {}; }, "at least one point");
  refused("positions not 3 per point", [](GlbPoints& g) { g.positions.pop_back(); }, "3 position values");
  refused("colours short", [](GlbPoints& g) { g.rgb.pop_back(); }, "colour values");
  refused("property short", [](GlbPoints& g) { g.properties[2].values.resize(8 * 19); }, "\"gps_time\" (f64) needs 160 bytes");
  refused("name not an identifier", [](GlbPoints& g) { g.properties[0].name = "2nd"; }, "not an identifier");
  refused("names equal once upper-cased", [](GlbPoints& g) { g.properties[3].name = "INTENSITY"; }, "_INTENSITY");
  refused("name of the feature IDs", [](GlbPoints& g) { g.properties[0].name = "feature_id_0"; }, "_FEATURE_ID_0");
  refused("feature IDs out of range", [](GlbPoints& g) { g.feature_id_property = 4; }, "feature_id_property 4");
  refused("feature IDs of f64", [](GlbPoints& g) { g.feature_id_property = 2; }, "must be u8 or u16");
  refused("position NaN", [](GlbPoints& g) { g.positions[4] = NAN; }, "not finite");
  refused("gps_time infinite", [](GlbPoints& g) {
    const double inf = INFINITY;
    std::memcpy(g.properties[2].values.data(), &inf, 8);
  }, "not finite");
}

}  // namespace
}  // namespace mv::test
