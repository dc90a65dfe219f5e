// Plain references of the mask post-processing kernels (tests only): a 5x5 binary median with the border
// repeated and an erosion by the octagon |dx|, |dy| <= r, (|dx| + |dy|)^2 <= 2 r^2 that ignores pixels past the
// border. Masks 0 / non-zero in, 0 / 255 out.
#pragma once
#include <cstdint>
#include <vector>

namespace mv::ref {

std::vector<uint8_t> median5(const std::vector<uint8_t>& mask, uint32_t width, uint32_t height);
std::vector<uint8_t> erode_octagon(const std::vector<uint8_t>& mask, uint32_t width, uint32_t height, uint32_t radius);

}  // namespace mv::ref
