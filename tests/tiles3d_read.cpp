#include "tiles3d_read.h"

#include <gtest/gtest.h>

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

}  // namespace

PntsRead read_pnts(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<char> b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
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
  return r;
}

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

}  // namespace mv::test
