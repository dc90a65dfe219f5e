#include "pnts_file.h"

#include <nlohmann/json.hpp>

#include <bit>
#include <cstring>
#include <string>

#include "megavox/error.h"

namespace mv::io {

// Floats and counts are copied as they lie in memory; the format is little-endian.
static_assert(std::endian::native == std::endian::little);

namespace {

void put_u32(std::vector<uint8_t>& out, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i) out[at + i] = static_cast<uint8_t>(v >> (8 * i));  // little-endian, as the spec says
}

size_t padded8(size_t n) { return (n + 7) & ~size_t{7}; }

const char* pnts_component_type(PointProperty::Type t) {
  using T = PointProperty::Type;
  switch (t) {
    case T::u8: return "UNSIGNED_BYTE";
    case T::i8: return "BYTE";
    case T::u16: return "UNSIGNED_SHORT";
    case T::i16: return "SHORT";
    case T::u32: return "UNSIGNED_INT";
    case T::i32: return "INT";
    case T::f32: return "FLOAT";
    case T::f64: return "DOUBLE";
  }
  return "?";
}

}  // namespace

std::vector<uint8_t> encode_pnts(const PntsTile& t) {
  const size_t points = t.positions.size() / 3;
  if (t.positions.size() != 3 * points || (!t.rgb.empty() && t.rgb.size() != 3 * points))
    throw Error("a .pnts tile needs 3 position and 3 colour values per point");
  constexpr size_t kHeader = 28;
  const size_t pos_bytes = 12 * points;

  nlohmann::json ft = {{"POINTS_LENGTH", points},
                       {"RTC_CENTER", {t.rtc_center[0], t.rtc_center[1], t.rtc_center[2]}},
                       {"POSITION", {{"byteOffset", 0}}}};
  if (!t.rgb.empty()) ft["RGB"] = {{"byteOffset", pos_bytes}};
  std::string json = ft.dump();
  json.resize(padded8(kHeader + json.size()) - kHeader, ' ');
  const size_t bin_bytes = padded8(pos_bytes + t.rgb.size());

  // The batch table: each property 8-aligned in the binary body (its componentType's size divides 8).
  nlohmann::json bt = nlohmann::json::object();
  size_t bt_bin_bytes = 0;
  for (const PointProperty& p : t.properties) {
    if (p.values.size() != point_property_size(p.type) * points)
      throw Error("a .pnts batch table property \"" + p.name + "\" needs one value per point");
    if (bt.contains(p.name)) throw Error("a .pnts batch table property \"" + p.name + "\" repeats");
    bt[p.name] = {{"byteOffset", bt_bin_bytes}, {"componentType", pnts_component_type(p.type)}, {"type", "SCALAR"}};
    bt_bin_bytes = padded8(bt_bin_bytes + p.values.size());
  }
  std::string bt_json = t.properties.empty() ? std::string() : bt.dump();
  bt_json.resize(padded8(bt_json.size()), ' ');  // everything before it ends on 8 bytes already
  const size_t total = kHeader + json.size() + bin_bytes + bt_json.size() + bt_bin_bytes;
  if (total > UINT32_MAX) throw Error("a .pnts tile of " + std::to_string(points) + " points exceeds 4 GiB");

  std::vector<uint8_t> out(total, 0);
  std::memcpy(out.data(), "pnts", 4);
  put_u32(out, 4, 1);  // version
  put_u32(out, 8, static_cast<uint32_t>(total));
  put_u32(out, 12, static_cast<uint32_t>(json.size()));
  put_u32(out, 16, static_cast<uint32_t>(bin_bytes));
  put_u32(out, 20, static_cast<uint32_t>(bt_json.size()));
  put_u32(out, 24, static_cast<uint32_t>(bt_bin_bytes));
  std::memcpy(out.data() + kHeader, json.data(), json.size());
  uint8_t* bin = out.data() + kHeader + json.size();
  if (pos_bytes) std::memcpy(bin, t.positions.data(), pos_bytes);
  if (!t.rgb.empty()) std::memcpy(bin + pos_bytes, t.rgb.data(), t.rgb.size());
  uint8_t* bt_at = bin + bin_bytes;
  if (!bt_json.empty()) std::memcpy(bt_at, bt_json.data(), bt_json.size());
  bt_at += bt_json.size();
  for (const PointProperty& p : t.properties) {
    const size_t at = bt[p.name]["byteOffset"];
    if (!p.values.empty()) std::memcpy(bt_at + at, p.values.data(), p.values.size());
  }
  return out;
}

}  // namespace mv::io
