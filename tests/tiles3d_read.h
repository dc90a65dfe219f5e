// Reading a written 3D Tiles tileset back for the tests: tileset.json, .pnts and .glb tiles, parsed by hand so
// the checks do not share code with the writer (meshopt views are decoded by meshoptimizer's own decoder).
#pragma once
#include <nlohmann/json.hpp>

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace mv::test {

struct PntsRead {
  uint32_t magic_ok = 0, version = 0, byte_length = 0, ft_json = 0, ft_bin = 0, bt_json = 0, bt_bin = 0;
  uint64_t file_size = 0;
  nlohmann::json feature_table, batch_table;
  std::vector<float> positions;
  std::vector<uint8_t> rgb;
  std::map<std::string, std::vector<double>> properties;  // the batch table's, one value per point
};

// The header, the feature table JSON and the POSITION / RGB arrays it points at, and the batch table's
// properties. Fails the test (ADD_FAILURE) and returns what it could read when the file is malformed.
PntsRead read_pnts(const std::string& path);

struct GlbRead {
  nlohmann::json gltf;
  uint64_t points = 0;
  std::vector<double> positions;  // 3 per point, in the tileset's z-up frame: the node's transform applied, then
                                  // glTF's y-up turned back to z-up as a 3D Tiles runtime does
  double step = 0;                // the node's quantization step (its scale)
  std::vector<uint8_t> rgb;       // 3 per point, or empty
  std::map<std::string, std::vector<double>> properties;  // EXT_structural_metadata's, offset and scale applied
  std::vector<uint32_t> feature_ids;                      // EXT_mesh_features' featureIds[0], or empty
  std::string feature_label;
};

// The GLB container, the accessors of the single POINTS primitive (meshopt views decoded) and the property
// attributes. Fails the test (ADD_FAILURE) and returns what it could read when the file is malformed.
GlbRead read_glb(const std::string& path);

nlohmann::json read_json(const std::string& path);

}  // namespace mv::test
