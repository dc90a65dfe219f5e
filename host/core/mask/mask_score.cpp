#include "mask_score.h"

#include <algorithm>
#include <cmath>

#include "megavox/error.h"

namespace mv::mask {

MaskBox box_from_truth(const std::vector<uint16_t>& truth, uint32_t W, uint32_t H) {
  long x0 = W, y0 = H, x1 = -1, y1 = -1;
  for (uint32_t y = 0; y < H; ++y)
    for (uint32_t x = 0; x < W; ++x)
      if (truth[size_t{y} * W + x] == 255) x0 = std::min<long>(x0, x), x1 = std::max<long>(x1, x), y0 = std::min<long>(y0, y), y1 = std::max<long>(y1, y);
  if (x1 < 0) throw Error("mask: the ground truth has no foreground pixel");
  const long mx = std::lround(0.05 * double(x1 - x0 + 1)), my = std::lround(0.05 * double(y1 - y0 + 1));
  x0 = std::max(0L, x0 - mx), y0 = std::max(0L, y0 - my);
  x1 = std::min(long{W} - 1, x1 + mx), y1 = std::min(long{H} - 1, y1 + my);
  if (x0 == 0 && y0 == 0 && x1 == long{W} - 1 && y1 == long{H} - 1 && W > 2 && H > 2) ++x0, ++y0, --x1, --y1;
  return MaskBox{uint32_t(x0), uint32_t(y0), uint32_t(x1 - x0 + 1), uint32_t(y1 - y0 + 1)};
}

double mask_error(const std::vector<uint8_t>& mask, const std::vector<uint16_t>& truth) {
  if (mask.size() != truth.size()) throw Error("mask: the mask and the ground truth differ in size");
  size_t labelled = 0, wrong = 0;
  for (size_t i = 0; i < mask.size(); ++i) {
    if (truth[i] != 0 && truth[i] != 255) continue;
    ++labelled;
    wrong += (mask[i] != 0) != (truth[i] == 255);
  }
  return labelled == 0 ? 0.0 : double(wrong) / double(labelled);
}

}  // namespace mv::mask
