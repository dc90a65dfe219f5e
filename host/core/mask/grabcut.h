// GrabCut on the host (Rother, Kolmogorov, Blake 2004, as OpenCV implements it): mixtures, data terms and
// contrast-sensitive 8-neighbour smoothness in double, quantized to an integer grid graph whose min-cut a
// caller supplies (the device kernels, or Boost's BK in tests and benchmarks).
//
// Quantization: every capacity is llround(w * scale), the total kept within room = 2^31 - 1 - capacities
// whatever the rounding. The first iteration takes scale = min(256, room / (2 * sum of all weights)): half the
// room, the other half left for later iterations' sums and a warm start's growth (MinCutFlow). Later ones keep
// the scale while their sum fits the room, so their edges stay the same and each cut can start from the last
// one's flow. Before that a pixel's two terminal weights lose their common part (min of the two), which
// changes every cut by the same constant and no label.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "megavox/grid_graph.h"
#include "megavox/raster.h"

namespace mv::mask {

// Per-pixel labels, OpenCV's numbering, plus "unknown" (a seed map's 128 with nothing else said): no hard
// constraint and not used to seed the mixtures; after the first cut it is a probable label like any other.
enum Label : uint8_t { kBackground = 0, kForeground = 1, kProbableBackground = 2, kProbableForeground = 3, kUnknown = 4 };

struct GrabCutOptions {
  uint32_t iterations = 5;  // at most; stops early when no label changes
  double gamma = 50;        // smoothness weight (diagonals gamma / sqrt 2)
  double lambda = 450;      // hard-label terminal weight: 9 gamma, above any pixel's summed smoothness
};

struct GrabCutResult {
  std::vector<uint8_t> labels;  // final labels (kBackground .. kProbableForeground)
  uint32_t iterations = 0;      // cuts made
  uint64_t cut_value = 0;       // the last cut's value, in quantized units
  double scale = 0;             // the last graph's quantization scale
};

using MinCutFn = std::function<MinCut(const GridGraph&)>;

// Colours in 0..255 (an image of other max_value scaled; grey replicated to three channels).
std::vector<std::array<double, 3>> image_colours(const RasterImage& image);

// OpenCV's beta: 1 / (2 * mean squared colour difference over all 8-neighbour pairs), 0 for a flat image.
double smoothness_beta(const std::vector<std::array<double, 3>>& colours, uint32_t width, uint32_t height);

// Runs GrabCut from `labels` (the start: every value a Label). Throws mv::Error when the start leaves the
// foreground or the background without a pixel to learn from.
GrabCutResult grabcut(const RasterImage& image, std::vector<uint8_t> labels, const GrabCutOptions& options,
                      const MinCutFn& cut);

// The labels of a box start: outside sure background, inside probable foreground.
std::vector<uint8_t> box_labels(uint32_t width, uint32_t height, uint32_t x, uint32_t y, uint32_t w, uint32_t h);

// 0/255 per pixel from labels (foreground and probable foreground are 255).
std::vector<uint8_t> labels_to_mask(const std::vector<uint8_t>& labels);

}  // namespace mv::mask
