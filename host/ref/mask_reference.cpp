#include "mask_reference.h"

#include <algorithm>
#include <cstdlib>

namespace mv::ref {

std::vector<uint8_t> median5(const std::vector<uint8_t>& m, uint32_t w, uint32_t h) {
  std::vector<uint8_t> out(m.size());
  for (long y = 0; y < long{h}; ++y)
    for (long x = 0; x < long{w}; ++x) {
      std::vector<uint8_t> window;
      for (long dy = -2; dy <= 2; ++dy)
        for (long dx = -2; dx <= 2; ++dx) {
          const long sx = std::clamp(x + dx, 0L, long{w} - 1), sy = std::clamp(y + dy, 0L, long{h} - 1);
          window.push_back(m[size_t(sy) * w + size_t(sx)] ? 1 : 0);
        }
      std::nth_element(window.begin(), window.begin() + 12, window.end());
      out[size_t(y) * w + size_t(x)] = window[12] ? 255 : 0;
    }
  return out;
}

std::vector<uint8_t> erode_octagon(const std::vector<uint8_t>& m, uint32_t w, uint32_t h, uint32_t radius) {
  const long r = radius;
  std::vector<uint8_t> out(m.size());
  for (long y = 0; y < long{h}; ++y)
    for (long x = 0; x < long{w}; ++x) {
      bool keep = true;
      for (long dy = -r; dy <= r && keep; ++dy)
        for (long dx = -r; dx <= r && keep; ++dx) {
          const long l1 = std::labs(dx) + std::labs(dy);
          if (l1 * l1 > 2 * r * r) continue;
          const long sx = x + dx, sy = y + dy;
          if (sx < 0 || sy < 0 || sx >= long{w} || sy >= long{h}) continue;
          keep = m[size_t(sy) * w + size_t(sx)] != 0;
        }
      out[size_t(y) * w + size_t(x)] = keep ? 255 : 0;
    }
  return out;
}

}  // namespace mv::ref
