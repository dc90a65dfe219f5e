// megavox — the histogram classifier that starts GrabCut without a box (`megavox mask train`, .mvm files):
// plain data. Colour images: a 32 x 32 hue x saturation histogram (value dropped, robust to flash shading;
// OpenCV's 8-bit HSV: hue in 0..360 degrees, saturation (max - min) / max); one-channel images (range or
// reflectance maps): 32 bins of the value over the format's range. A bin holds the training pixels of each
// side; a pixel's probability is fg / (fg + bg) of its bin, 0 for a bin no training pixel fell in.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "megavox/raster.h"

namespace mv {

struct MaskModel {
  static constexpr uint32_t kBins1 = 32;           // per axis
  uint32_t channels = 3;                           // 3 (1024 bins) or 1 (32 bins)
  std::vector<uint64_t> fg, bg;                    // training pixels per bin

  static MaskModel empty(uint32_t channels);
  uint32_t bins() const { return channels == 3 ? kBins1 * kBins1 : kBins1; }
  uint32_t bin_of(const RasterImage& image, size_t pixel) const;
  double probability(const RasterImage& image, size_t pixel) const;
  // Adds an image's pixels under a mask: 255 foreground, 0 background, anything else (a 128 band) skipped.
  // Throws mv::Error when the channels or the sizes differ.
  void train(const RasterImage& image, const std::vector<uint16_t>& mask, uint32_t mask_width, uint32_t mask_height);
};

}  // namespace mv
