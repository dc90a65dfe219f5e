// Reading a written 3D Tiles tileset back for the tests: tileset.json and .pnts tiles, parsed by hand so the
// checks do not share code with the writer.
#pragma once
#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace mv::test {

struct PntsRead {
  uint32_t magic_ok = 0, version = 0, byte_length = 0, ft_json = 0, ft_bin = 0, bt_json = 0, bt_bin = 0;
  uint64_t file_size = 0;
  nlohmann::json feature_table;
  std::vector<float> positions;
  std::vector<uint8_t> rgb;
};

// The header, the feature table JSON and the POSITION / RGB arrays it points at. Fails the test (ADD_FAILURE)
// and returns what it could read when the file is malformed.
PntsRead read_pnts(const std::string& path);

nlohmann::json read_json(const std::string& path);

}  // namespace mv::test
