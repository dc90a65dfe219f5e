// megavox — a decoded photograph or range map: plain data (read by host/formats/io/image_reader.h).
#pragma once
#include <cstdint>
#include <vector>

namespace mv {

struct RasterImage {
  uint32_t width = 0;
  uint32_t height = 0;
  uint32_t channels = 0;          // 1 (grey, range or reflectance) or 3 (RGB)
  uint32_t max_value = 255;       // the largest sample the format allows: 255, 65535, or a PNM's maxval
  std::vector<uint16_t> samples;  // row-major, `channels` per pixel
};

}  // namespace mv
