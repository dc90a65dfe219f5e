// megavox — lossy colour quantization before palette compression (docs/colour.md): at most 2^bits distinct
// colours, clustered by weighted k-means in CIELAB (D65), as Kol's thesis (ch. 2.4.3) clusters in CIELAB; the
// errors it reports are the thesis's (mean and max per RGB channel, mean and max ΔE CIE94).
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

namespace mv {

struct ColourQuantizeReport {
  uint32_t bits = 24;
  uint64_t colours_in = 0, colours_out = 0;  // distinct colours before and after
  std::array<double, 3> mean_rgb{}, max_rgb{};  // absolute error per channel over every entry
  double mean_delta_e = 0, max_delta_e = 0;     // ΔE CIE94 (k_L = 1, K1 = 0.045, K2 = 0.015), the input as reference
  uint32_t iterations = 0;                      // Lloyd iterations run
  double seconds = 0;
};

// Replaces every colour of `rgb` (3 bytes per entry) by its cluster's: the distinct colours, weighted by their
// entries, start from a median cut in CIELAB (splitting the box of largest weighted spread at its weighted
// median) and are refined by Lloyd iterations (nearest centre by a k-d tree; ties to the lower centre); each
// cluster's colour is its CIELAB centroid back in 8-bit sRGB. Deterministic. bits 24, or no more distinct
// colours than 2^bits: unchanged. Throws mv::Error for bits outside 1 .. 24.
//
// `nearest`, when given, runs each Lloyd round's assignment instead of the host (a device kernel: quantize.h):
// every colour's nearest centre into `cluster` (its last one on entry; the nearest by squared CIELAB distance,
// the lower index among equals), true when any changed. `order` is the centres' k-d tree (centre_tree_order).
using NearestCentres = std::function<bool(const std::vector<std::array<double, 3>>& lab,
                                          const std::vector<std::array<double, 3>>& centres,
                                          const std::vector<uint32_t>& order, std::vector<uint32_t>& cluster)>;
ColourQuantizeReport quantize_colours(std::vector<uint8_t>& rgb, uint32_t bits, const NearestCentres& nearest = {});

// The host's assignment, each colour's nearest centre by a search of the tree (the device kernel's reference).
bool nearest_centres_on_host(const std::vector<std::array<double, 3>>& lab,
                             const std::vector<std::array<double, 3>>& centres, const std::vector<uint32_t>& order,
                             std::vector<uint32_t>& cluster);

// The k-d tree of `centres` as an array of their indices: the subtree over [lo, hi) has its root at mid = lo +
// (hi - lo) / 2, split on axis depth % 3 at the median by (value, index), [lo, mid) and [mid + 1, hi) below.
std::vector<uint32_t> centre_tree_order(const std::vector<std::array<double, 3>>& centres);

// sRGB (8 bits per channel) to CIELAB, D65 white.
std::array<double, 3> srgb_to_lab(const uint8_t rgb[3]);
// ΔE CIE94 of `lab` against the reference `ref` (graphic arts: k_L = 1, K1 = 0.045, K2 = 0.015).
double delta_e94(const std::array<double, 3>& ref, const std::array<double, 3>& lab);

}  // namespace mv
