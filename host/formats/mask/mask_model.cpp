#include "megavox/mask_model.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "megavox/error.h"

namespace mv {

MaskModel MaskModel::empty(uint32_t channels) {
  if (channels != 1 && channels != 3) throw Error("mask model: 1 or 3 channels, not " + std::to_string(channels));
  MaskModel m;
  m.channels = channels;
  m.fg.assign(m.bins(), 0);
  m.bg.assign(m.bins(), 0);
  return m;
}

uint32_t MaskModel::bin_of(const RasterImage& image, size_t pixel) const {
  const double to255 = 255.0 / std::max<uint32_t>(image.max_value, 1);
  if (channels == 1) {
    const double v = image.samples[pixel * image.channels] * to255;
    return std::min<uint32_t>(kBins1 - 1, static_cast<uint32_t>(v * kBins1 / 256.0));
  }
  const double r = image.samples[pixel * 3] * to255, g = image.samples[pixel * 3 + 1] * to255,
               b = image.samples[pixel * 3 + 2] * to255;
  const double hi = std::max({r, g, b}), lo = std::min({r, g, b}), range = hi - lo;
  double hue = 0;
  if (range > 0) {
    if (hi == r) hue = 60.0 * (g - b) / range;
    else if (hi == g) hue = 120.0 + 60.0 * (b - r) / range;
    else hue = 240.0 + 60.0 * (r - g) / range;
    if (hue < 0) hue += 360.0;
  }
  const double sat = hi > 0 ? range / hi : 0;
  const uint32_t hb = std::min<uint32_t>(kBins1 - 1, static_cast<uint32_t>(hue * kBins1 / 360.0));
  const uint32_t sb = std::min<uint32_t>(kBins1 - 1, static_cast<uint32_t>(sat * kBins1));
  return hb * kBins1 + sb;
}

double MaskModel::probability(const RasterImage& image, size_t pixel) const {
  const uint32_t b = bin_of(image, pixel);
  const uint64_t total = fg[b] + bg[b];
  return total == 0 ? 0.0 : static_cast<double>(fg[b]) / static_cast<double>(total);
}

void MaskModel::train(const RasterImage& image, const std::vector<uint16_t>& mask, uint32_t mw, uint32_t mh) {
  if (image.channels != channels)
    throw Error("mask model: a " + std::to_string(channels) + "-channel model cannot learn from a " +
                std::to_string(image.channels) + "-channel image");
  if (mw != image.width || mh != image.height)
    throw Error("mask model: the mask is " + std::to_string(mw) + " x " + std::to_string(mh) + ", its image " +
                std::to_string(image.width) + " x " + std::to_string(image.height));
  for (size_t i = 0; i < mask.size(); ++i) {
    if (mask[i] == 255) ++fg[bin_of(image, i)];
    else if (mask[i] == 0) ++bg[bin_of(image, i)];
  }
}

}  // namespace mv
