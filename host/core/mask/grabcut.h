// GrabCut (Rother, Kolmogorov, Blake 2004, as OpenCV implements it) on a device: k-means, the mixtures' moments,
// data terms, contrast-sensitive 8-neighbour smoothness and their quantization to an integer grid graph are
// kernels (grabcut_kernels.h); the host fits each mixture component from the summed moments and asks a caller
// for the graph's min-cut (the device min-cut, or Boost's BK in tests and benchmarks). Every step is the same
// bits on every device (docs/masks.md, "Exact GrabCut"), so masks are too.
//
// Colours are 8-bit: samples of another max_value are scaled to 0..255 and rounded (grey replicated).
//
// Quantization: every capacity is llround(w * scale), the total kept within room = 2^31 - 1 - capacities
// whatever the rounding. The first iteration takes scale = min(256, room / (2 * sum of all weights)): half the
// room, the other half left for later iterations' sums and a warm start's growth (MinCutFlow). Later ones keep
// the scale while their sum fits the room, so their edges stay the same and each cut can start from the last
// one's flow. Before that a pixel's two terminal weights lose their common part (min of the two), which
// changes every cut by the same constant and no label. The sum of all weights is taken in fixed point (each
// weight rounded to 2^-20), an integer sum, so the scale is the same on every device.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "megavox/device.h"
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

// Runs GrabCut on `dev` from `labels` (the start: every value a Label). Throws mv::Error when the start leaves
// the foreground or the background without a pixel to learn from.
GrabCutResult grabcut(Device& dev, const RasterImage& image, const std::vector<uint8_t>& labels,
                      const GrabCutOptions& options, const MinCutFn& cut);

// The labels of a box start: outside sure background, inside probable foreground.
std::vector<uint8_t> box_labels(uint32_t width, uint32_t height, uint32_t x, uint32_t y, uint32_t w, uint32_t h);

// 0/255 per pixel from labels (foreground and probable foreground are 255).
std::vector<uint8_t> labels_to_mask(const std::vector<uint8_t>& labels);

}  // namespace mv::mask
