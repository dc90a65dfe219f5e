// Mask post-processing on a device: median, then erosion (kernels/common/mask_post.h), 2-D launches.
#include <string>

#include "common/mask_post.h"
#include "megavox/error.h"
#include "megavox/mask.h"

namespace mv {

std::vector<uint8_t> postprocess_mask(Device& dev, const std::vector<uint8_t>& mask, uint32_t width, uint32_t height,
                                      uint32_t erode_radius) {
  const size_t n = size_t{width} * height;
  if (n == 0 || mask.size() != n) throw Error("postprocess_mask: the mask does not match its size");
  if (erode_radius > MV_MASK_MAX_RADIUS)
    throw Error("erosion radius " + std::to_string(erode_radius) + " is over " + std::to_string(MV_MASK_MAX_RADIUS));
  std::vector<uint32_t> words(n);
  for (size_t i = 0; i < n; ++i) words[i] = mask[i] != 0;
  Buffer a = dev.alloc(n * 4, "mask"), b = dev.alloc(n * 4, "mask after the median");
  dev.upload(a, words.data(), n * 4);
  const uint32_t lx = 8, ly = 8;
  const LaunchGrid grid{{(width + lx - 1) / lx, (height + ly - 1) / ly}, {lx, ly}};
  const MvMaskPostParams p{width, height, erode_radius, 0};
  dev.dispatch(dev.kernel(KernelId::mask_median5), grid, {&a, &b}, p);
  dev.barrier();
  const Buffer* out = &b;
  if (erode_radius > 0) {
    dev.dispatch(dev.kernel(KernelId::mask_erode), grid, {&b, &a}, p);
    dev.barrier();
    out = &a;
  }
  dev.download(*out, words.data(), n * 4);
  std::vector<uint8_t> result(n);
  for (size_t i = 0; i < n; ++i) result[i] = words[i] ? 255 : 0;
  return result;
}

}  // namespace mv
