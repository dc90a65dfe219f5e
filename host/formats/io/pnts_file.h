// 3D Tiles 1.0 Point Cloud tiles (.pnts): a 28-byte header, a feature table (JSON, then binary) and, when the
// points carry properties, a batch table of per-point properties. Positions are float32 relative to RTC_CENTER
// (double), colours RGB uint8.
#pragma once
#include <cstdint>
#include <vector>

#include "glb_points.h"

namespace mv::io {

struct PntsTile {
  double rtc_center[3] = {0, 0, 0};
  std::vector<float> positions;  // 3 per point, relative to rtc_center
  std::vector<uint8_t> rgb;      // 3 per point, or empty for none
  // Per-point properties: one value of its type per point. Without BATCH_ID in the feature table the batch
  // table's length is POINTS_LENGTH (3D Tiles 1.0, Point Cloud, "Batch Table"), so no BATCH_LENGTH is written.
  // Types map to the batch table's componentType one to one (u8 UNSIGNED_BYTE ... f64 DOUBLE).
  std::vector<PointProperty> properties;
};

// The tile's bytes: each JSON padded with spaces and each binary body with zeros to 8 bytes, so every part
// starts and the tile ends on an 8-byte boundary; every batch table property starts 8-aligned in its body.
// Throws mv::Error when the sizes do not match the point count, a name repeats or the tile would exceed 4 GiB.
std::vector<uint8_t> encode_pnts(const PntsTile& tile);

}  // namespace mv::io
