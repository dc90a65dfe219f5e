#include "tiles3d_properties.h"

#include <cctype>
#include <cstring>
#include <set>

#include "megavox/error.h"

namespace mv::io {

namespace {

// [A-Za-z_][A-Za-z0-9_]*, as EXT_structural_metadata asks of property names.
std::string t3p_identifier(const std::string& name) {
  std::string id;
  for (char c : name) id += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  if (id.empty() || std::isdigit(static_cast<unsigned char>(id[0]))) id = "_" + id;
  return id;
}

std::string t3p_upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// Names in use, upper-cased: glb attribute names ("_" + upper case) must differ, and _FEATURE_ID_0 is taken.
struct T3pNames {
  std::set<std::string> used = {"FEATURE_ID_0"};
  std::string claim(const std::string& wanted) {
    const std::string base = t3p_identifier(wanted);
    std::string name = base;
    for (int k = 2; !used.insert(t3p_upper(name)).second; ++k) name = base + "_" + std::to_string(k);
    return name;
  }
};

bool t3p_store_type(PointFieldType t, PointProperty::Type& out) {
  using F = PointFieldType;
  using P = PointProperty::Type;
  switch (t) {
    case F::u8: out = P::u8; return true;
    case F::i8: out = P::i8; return true;
    case F::u16: out = P::u16; return true;
    case F::i16: out = P::i16; return true;
    case F::u32: out = P::u32; return true;
    case F::i32: out = P::i32; return true;
    case F::f32: out = P::f32; return true;
    case F::f64: out = P::f64; return true;
    case F::u64:
    case F::i64: return false;
  }
  return false;
}

template <class T>
double t3p_load(const uint8_t* at) {
  T v;
  std::memcpy(&v, at, sizeof v);
  return static_cast<double>(v);
}

double t3p_value(PointFieldType t, const uint8_t* at) {
  using F = PointFieldType;
  switch (t) {
    case F::u8: return t3p_load<uint8_t>(at);
    case F::i8: return t3p_load<int8_t>(at);
    case F::u16: return t3p_load<uint16_t>(at);
    case F::i16: return t3p_load<int16_t>(at);
    case F::u32: return t3p_load<uint32_t>(at);
    case F::i32: return t3p_load<int32_t>(at);
    case F::u64: return t3p_load<uint64_t>(at);
    case F::i64: return t3p_load<int64_t>(at);
    case F::f32: return t3p_load<float>(at);
    case F::f64: return t3p_load<double>(at);
  }
  return 0;
}

void t3p_check_columns(const PointHierarchy& h) {
  const uint64_t n = h.points.size();
  const PointCloudInfo& s = h.source;
  if ((s.attributes & kPointIntensity) && h.points.intensity.size() != n)
    throw Error("the point hierarchy says it has intensity, but holds " + std::to_string(h.points.intensity.size()) +
                " values for " + std::to_string(n) + " points");
  if ((s.attributes & kPointNormal) && h.points.normal.size() != 3 * n)
    throw Error("the point hierarchy says it has normals, but holds " + std::to_string(h.points.normal.size()) +
                " values for " + std::to_string(n) + " points");
  if ((s.attributes & kPointExtra) && h.points.extra.size() != uint64_t{s.extra_bytes} * n)
    throw Error("the point hierarchy's attribute records hold " + std::to_string(h.points.extra.size()) +
                " bytes, not " + std::to_string(s.extra_bytes) + " for each of its " + std::to_string(n) + " points");
}

}  // namespace

TileProperties tile_properties(const PointHierarchy& h) {
  t3p_check_columns(h);
  const PointCloudInfo& s = h.source;
  TileProperties out;
  T3pNames names;
  using P = PointProperty::Type;
  if (s.attributes & kPointIntensity) {
    TileProperty p;
    p.name = names.claim("intensity");
    p.type = P::u16;
    p.from = TileProperty::From::intensity;
    out.properties.push_back(p);
  }
  if (s.attributes & kPointNormal) {
    for (uint32_t a = 0; a < 3; ++a) {
      TileProperty p;
      p.name = names.claim(std::string("normal_") + "xyz"[a]);
      p.type = P::f32;
      p.from = TileProperty::From::normal;
      p.offset = a;
      out.properties.push_back(p);
    }
  }
  if (!(s.attributes & kPointExtra) || s.extra_bytes == 0) return out;
  if (s.fields.empty()) {
    out.skipped.push_back({"extra_bytes", std::to_string(s.extra_bytes) + (s.extra_bytes == 1 ? " byte" : " bytes") +
                                              " a point that no field names"});
    return out;
  }
  for (const PointField& f : s.fields) {
    const uint64_t bytes = uint64_t{point_field_size(f.type)} * f.count;
    if (f.count == 0 || f.offset + bytes > s.extra_bytes)
      throw Error("the point hierarchy's field \"" + f.name + "\" (" + std::to_string(f.count) + " x " +
                  point_field_type_name(f.type) + " at byte " + std::to_string(f.offset) + ") lies beyond its " +
                  std::to_string(s.extra_bytes) + "-byte attribute record");
    PointProperty::Type stored;
    const bool scaled = f.scale != 1 || f.add != 0;
    if (!t3p_store_type(f.type, stored)) {
      out.skipped.push_back({f.name, std::string(point_field_type_name(f.type)) +
                                         ": neither glTF nor the 1.0 batch table has a 64-bit integer type, and a "
                                         "double would round values past 2^53"});
      continue;
    }
    if (f.count > 3) {
      out.skipped.push_back({f.name, std::to_string(f.count) + " x " + point_field_type_name(f.type) +
                                         " a point: a run of bytes, not a quantity a viewer can show"});
      continue;
    }
    for (uint32_t k = 0; k < f.count; ++k) {
      TileProperty p;
      p.name = names.claim(f.count == 1 ? f.name : f.name + "_" + std::to_string(k));
      p.type = scaled ? P::f64 : stored;
      p.from = TileProperty::From::field;
      p.offset = f.offset + k * point_field_size(f.type);
      p.field_type = f.type;
      p.scaled = scaled;
      p.scale = f.scale, p.add = f.add;
      if (f.name == "classification" && f.count == 1 && !scaled && (stored == P::u8 || stored == P::u16) &&
          out.classification < 0)
        out.classification = static_cast<int>(out.properties.size());
      out.properties.push_back(std::move(p));
    }
  }
  return out;
}

std::vector<uint8_t> tile_property_values(const PointHierarchy& h, const TileProperty& p, uint64_t first,
                                          uint64_t count) {
  const size_t size = point_property_size(p.type);
  std::vector<uint8_t> out(size * count);
  uint8_t* to = out.data();
  switch (p.from) {
    case TileProperty::From::intensity:
      std::memcpy(to, h.points.intensity.data() + first, 2 * count);
      break;
    case TileProperty::From::normal:
      for (uint64_t i = 0; i < count; ++i) std::memcpy(to + 4 * i, &h.points.normal[3 * (first + i) + p.offset], 4);
      break;
    case TileProperty::From::field: {
      const uint64_t record = h.source.extra_bytes;
      const uint8_t* from = h.points.extra.data() + first * record + p.offset;
      if (!p.scaled) {  // the stored type is the field's own: the bytes as they are
        for (uint64_t i = 0; i < count; ++i) std::memcpy(to + size * i, from + record * i, size);
        break;
      }
      for (uint64_t i = 0; i < count; ++i) {
        const double v = t3p_value(p.field_type, from + record * i) * p.scale + p.add;
        std::memcpy(to + 8 * i, &v, 8);
      }
      break;
    }
  }
  return out;
}

}  // namespace mv::io
