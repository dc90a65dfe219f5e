#include "tiles3d_read.h"

#include <gtest/gtest.h>
#include <meshoptimizer.h>

#include <cstring>
#include <fstream>
#include <iterator>

namespace mv::test {

namespace {

uint32_t u32(const std::vector<char>& b, size_t at) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= uint32_t(static_cast<unsigned char>(b[at + i])) << (8 * i);
  return v;
}

std::vector<char> t3r_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<char>((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

template <class T>
double t3r_as(const char* at) {
  T v;
  std::memcpy(&v, at, sizeof v);
  return static_cast<double>(v);
}

// One value of a batch table componentType or a glTF componentType code, as a double; 0 bytes when unknown.
size_t t3r_size(const std::string& type) {
  if (type == "BYTE" || type == "UNSIGNED_BYTE") return 1;
  if (type == "SHORT" || type == "UNSIGNED_SHORT") return 2;
  if (type == "INT" || type == "UNSIGNED_INT" || type == "FLOAT") return 4;
  if (type == "DOUBLE") return 8;
  return 0;
}
double t3r_value(const std::string& type, const char* at) {
  if (type == "BYTE") return t3r_as<int8_t>(at);
  if (type == "UNSIGNED_BYTE") return t3r_as<uint8_t>(at);
  if (type == "SHORT") return t3r_as<int16_t>(at);
  if (type == "UNSIGNED_SHORT") return t3r_as<uint16_t>(at);
  if (type == "INT") return t3r_as<int32_t>(at);
  if (type == "UNSIGNED_INT") return t3r_as<uint32_t>(at);
  if (type == "FLOAT") return t3r_as<float>(at);
  return t3r_as<double>(at);
}
std::string t3r_gltf_type(int component_type) {
  switch (component_type) {
    case 5120: return "BYTE";
    case 5121: return "UNSIGNED_BYTE";
    case 5122: return "SHORT";
    case 5123: return "UNSIGNED_SHORT";
    case 5125: return "UNSIGNED_INT";
    case 5126: return "FLOAT";
  }
  return "?";
}

void t3r_batch_table(const std::string& path, PntsRead& r, const std::vector<char>& b) {
  const size_t at = 28 + size_t{r.ft_json} + r.ft_bin;
  if (at + r.bt_json + r.bt_bin > b.size()) {
    ADD_FAILURE() << path << ": the batch table runs past the end of the file";
    return;
  }
  r.batch_table = nlohmann::json::parse(std::string(b.data() + at, r.bt_json));
  const char* bin = b.data() + at + r.bt_json;
  const uint64_t n = r.feature_table.value("POINTS_LENGTH", uint64_t{0});
  for (const auto& [name, p] : r.batch_table.items()) {
    const std::string type = p.value("componentType", "");
    const uint64_t offset = p.value("byteOffset", uint64_t{0}), size = t3r_size(type);
    if (p.value("type", "") != "SCALAR" || size == 0 || offset % size != 0 || offset + size * n > r.bt_bin) {
      ADD_FAILURE() << path << ": batch table property " << name << " is not " << n << " aligned scalars: " << p;
      continue;
    }
    auto& v = r.properties[name];
    for (uint64_t i = 0; i < n; ++i) v.push_back(t3r_value(type, bin + offset + size * i));
  }
}

}  // namespace

PntsRead read_pnts(const std::string& path) {
  const std::vector<char> b = t3r_file(path);
  PntsRead r;
  r.file_size = b.size();
  if (b.size() < 28) {
    ADD_FAILURE() << path << ": " << b.size() << " bytes, shorter than the header";
    return r;
  }
  r.magic_ok = std::memcmp(b.data(), "pnts", 4) == 0;
  r.version = u32(b, 4), r.byte_length = u32(b, 8), r.ft_json = u32(b, 12), r.ft_bin = u32(b, 16);
  r.bt_json = u32(b, 20), r.bt_bin = u32(b, 24);
  if (28ull + r.ft_json + r.ft_bin > b.size()) {
    ADD_FAILURE() << path << ": the feature table runs past the end of the file";
    return r;
  }
  r.feature_table = nlohmann::json::parse(std::string(b.data() + 28, r.ft_json));  // trailing spaces are fine
  const char* bin = b.data() + 28 + r.ft_json;
  const uint64_t n = r.feature_table.value("POINTS_LENGTH", uint64_t{0});
  if (r.feature_table.contains("POSITION")) {
    const uint64_t at = r.feature_table["POSITION"]["byteOffset"];
    if (at + 12 * n > r.ft_bin) {
      ADD_FAILURE() << path << ": POSITION runs past the feature table's binary body";
    } else {
      r.positions.resize(3 * n);
      std::memcpy(r.positions.data(), bin + at, 12 * n);
    }
  }
  if (r.feature_table.contains("RGB")) {
    const uint64_t at = r.feature_table["RGB"]["byteOffset"];
    if (at + 3 * n > r.ft_bin) {
      ADD_FAILURE() << path << ": RGB runs past the feature table's binary body";
    } else {
      r.rgb.assign(bin + at, bin + at + 3 * n);
    }
  }
  if (r.bt_json) t3r_batch_table(path, r, b);
  return r;
}

namespace {

// A glb's JSON and its buffer views decoded: plain views sliced from the BIN chunk, meshopt views decoded.
struct T3rGlb {
  std::string path;
  nlohmann::json j;
  std::vector<char> bin;

  // The bytes of view v (its byteLength), or empty after a failure.
  std::vector<char> view(size_t v) const {
    const nlohmann::json& view = j.at("bufferViews").at(v);
    const size_t length = view.at("byteLength"), offset = view.value("byteOffset", size_t{0});
    std::vector<char> out(length);
    if (view.contains("extensions") && view["extensions"].contains("EXT_meshopt_compression")) {
      const nlohmann::json& m = view["extensions"]["EXT_meshopt_compression"];
      const size_t at = m.value("byteOffset", size_t{0}), packed = m.at("byteLength");
      const size_t count = m.at("count"), stride = m.at("byteStride");
      if (m.at("buffer") != 0 || m.at("mode") != "ATTRIBUTES" || at + packed > bin.size() || count * stride != length ||
          meshopt_decodeVertexBuffer(out.data(), count, stride, reinterpret_cast<const unsigned char*>(bin.data() + at),
                                     packed) != 0) {
        ADD_FAILURE() << path << ": meshopt view " << v << " does not decode: " << m;
        return {};
      }
      return out;
    }
    if (view.at("buffer") != 0 || offset + length > bin.size()) {
      ADD_FAILURE() << path << ": view " << v << " lies outside the BIN chunk";
      return {};
    }
    std::memcpy(out.data(), bin.data() + offset, length);
    return out;
  }

  // Accessor a's values as doubles (components per element given by its type), not normalized.
  std::vector<double> accessor(size_t a, size_t& components) const {
    const nlohmann::json& acc = j.at("accessors").at(a);
    const std::string type = acc.at("type");
    components = type == "SCALAR" ? 1 : type == "VEC2" ? 2 : type == "VEC3" ? 3 : 4;
    const std::string ct = t3r_gltf_type(acc.at("componentType"));
    const size_t size = t3r_size(ct), count = acc.at("count");
    const size_t v = acc.at("bufferView");
    const size_t stride = j["bufferViews"][v].value("byteStride", size * components);
    const size_t offset = acc.value("byteOffset", size_t{0});
    const std::vector<char> bytes = view(v);
    std::vector<double> out;
    if (bytes.empty() || size == 0 || (count - 1) * stride + offset + size * components > bytes.size()) {
      ADD_FAILURE() << path << ": accessor " << a << " does not fit its view";
      return out;
    }
    for (size_t i = 0; i < count; ++i)
      for (size_t c = 0; c < components; ++c)
        out.push_back(t3r_value(ct, bytes.data() + offset + stride * i + size * c));
    return out;
  }
};

// v rotated by the unit quaternion q = (x, y, z, w).
void t3r_rotate(const double q[4], double v[3]) {
  const double t[3] = {2 * (q[1] * v[2] - q[2] * v[1]), 2 * (q[2] * v[0] - q[0] * v[2]),
                       2 * (q[0] * v[1] - q[1] * v[0])};
  const double r[3] = {v[0] + q[3] * t[0] + q[1] * t[2] - q[2] * t[1], v[1] + q[3] * t[1] + q[2] * t[0] - q[0] * t[2],
                       v[2] + q[3] * t[2] + q[0] * t[1] - q[1] * t[0]};
  for (int a = 0; a < 3; ++a) v[a] = r[a];
}

}  // namespace

GlbRead read_glb(const std::string& path) {
  const std::vector<char> b = t3r_file(path);
  GlbRead r;
  if (b.size() < 28 || std::memcmp(b.data(), "glTF", 4) != 0 || u32(b, 4) != 2 || u32(b, 8) != b.size()) {
    ADD_FAILURE() << path << ": not a GLB 2 file of its stated length";
    return r;
  }
  const size_t json_len = u32(b, 12);
  if (std::memcmp(b.data() + 16, "JSON", 4) != 0 || 20 + json_len + 8 > b.size()) {
    ADD_FAILURE() << path << ": no JSON chunk first, or no room for the BIN chunk";
    return r;
  }
  T3rGlb g{path, nlohmann::json::parse(b.begin() + 20, b.begin() + 20 + json_len), {}};
  const size_t bin_at = 20 + json_len, bin_len = u32(b, bin_at);
  if (std::memcmp(b.data() + bin_at + 4, "BIN\0", 4) != 0 || bin_at + 8 + bin_len != b.size()) {
    ADD_FAILURE() << path << ": the BIN chunk is not the rest of the file";
    return r;
  }
  g.bin.assign(b.begin() + bin_at + 8, b.end());
  r.gltf = g.j;
  const nlohmann::json& prim = g.j.at("meshes").at(0).at("primitives").at(0);
  const nlohmann::json& attrs = prim.at("attributes");
  size_t components = 0;
  const std::vector<double> q = g.accessor(attrs.at("POSITION"), components);
  r.points = q.size() / 3;

  // The node: T * R * S, then y-up back to z-up ((x, y, z) -> (x, -z, y)).
  const nlohmann::json& node = g.j.at("nodes").at(0);
  const std::vector<double> t = node.value("translation", std::vector<double>{0, 0, 0});
  const std::vector<double> rot = node.value("rotation", std::vector<double>{0, 0, 0, 1});
  const std::vector<double> s = node.value("scale", std::vector<double>{1, 1, 1});
  r.step = s.at(0);
  for (size_t i = 0; i < r.points; ++i) {
    double v[3] = {q[3 * i] * s[0], q[3 * i + 1] * s[1], q[3 * i + 2] * s[2]};
    t3r_rotate(rot.data(), v);
    for (int a = 0; a < 3; ++a) v[a] += t[a];
    r.positions.insert(r.positions.end(), {v[0], -v[2], v[1]});
  }
  if (attrs.contains("COLOR_0")) {
    for (double c : g.accessor(attrs["COLOR_0"], components)) r.rgb.push_back(static_cast<uint8_t>(c));
  }

  if (prim.contains("extensions") && prim["extensions"].contains("EXT_structural_metadata")) {
    const size_t pa = prim["extensions"]["EXT_structural_metadata"].at("propertyAttributes").at(0);
    const nlohmann::json& meta = g.j.at("extensions").at("EXT_structural_metadata");
    for (const auto& [name, p] : meta.at("propertyAttributes").at(pa).at("properties").items()) {
      const std::string attribute = p.at("attribute");
      if (!attrs.contains(attribute)) {
        ADD_FAILURE() << path << ": property " << name << " names no attribute " << attribute;
        continue;
      }
      std::vector<double> v = g.accessor(attrs[attribute], components);
      const double offset = p.value("offset", 0.0), scale = p.value("scale", 1.0);
      for (double& x : v) x = offset + scale * x;
      r.properties[name] = std::move(v);
    }
  }
  if (prim.contains("extensions") && prim["extensions"].contains("EXT_mesh_features")) {
    const nlohmann::json& f = prim["extensions"]["EXT_mesh_features"].at("featureIds").at(0);
    r.feature_label = f.value("label", "");
    const std::string attribute = "_FEATURE_ID_" + std::to_string(f.at("attribute").get<int>());
    if (!attrs.contains(attribute)) {
      ADD_FAILURE() << path << ": no feature ID attribute " << attribute;
    } else {
      for (double id : g.accessor(attrs[attribute], components)) r.feature_ids.push_back(static_cast<uint32_t>(id));
    }
  }
  return r;
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

}  // namespace mv::test
