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
  const size_t total = kHeader + json.size() + bin_bytes;
  if (total > UINT32_MAX) throw Error("a .pnts tile of " + std::to_string(points) + " points exceeds 4 GiB");

  std::vector<uint8_t> out(total, 0);
  std::memcpy(out.data(), "pnts", 4);
  put_u32(out, 4, 1);  // version
  put_u32(out, 8, static_cast<uint32_t>(total));
  put_u32(out, 12, static_cast<uint32_t>(json.size()));
  put_u32(out, 16, static_cast<uint32_t>(bin_bytes));
  put_u32(out, 20, 0);  // batch table JSON
  put_u32(out, 24, 0);  // batch table binary
  std::memcpy(out.data() + kHeader, json.data(), json.size());
  uint8_t* bin = out.data() + kHeader + json.size();
  if (pos_bytes) std::memcpy(bin, t.positions.data(), pos_bytes);
  if (!t.rgb.empty()) std::memcpy(bin + pos_bytes, t.rgb.data(), t.rgb.size());
  return out;
}

}  // namespace mv::io
