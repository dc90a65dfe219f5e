// 3D Tiles 1.0 Point Cloud tiles (.pnts): a 28-byte header, a feature table (JSON, then binary) and no batch
// table. Positions are float32 relative to RTC_CENTER (double), colours RGB uint8.
#pragma once
#include <cstdint>
#include <vector>

namespace mv::io {

struct PntsTile {
  double rtc_center[3] = {0, 0, 0};
  std::vector<float> positions;  // 3 per point, relative to rtc_center
  std::vector<uint8_t> rgb;      // 3 per point, or empty for none
};

// The tile's bytes: JSON padded with spaces and binary with zeros to 8 bytes each, so the binary body starts
// and the tile ends on 8-byte boundaries.
std::vector<uint8_t> encode_pnts(const PntsTile& tile);

}  // namespace mv::io
