// Plain references of GrabCut's kernels (kernels/common/grabcut*.h; tests only), written from docs/masks.md's
// "Exact GrabCut" without the kernels' code: packed 8-bit colours, beta's sum, smoothness capacities, the
// mixture energies with exp and log evaluated by the same documented scheme (range reduction, the same
// polynomials, the same constants), data terms, moments, k-means steps, k-means++ seeding and label updates.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "megavox/raster.h"

namespace mv::ref {

struct GcComponent {
  bool present = false;
  double mean[3] = {};
  double inverse[9] = {};
  double energy = 0;  // -log(weight / sqrt(det))
};
using GcMixture = std::array<GcComponent, 5>;  // one side's

struct GcFit {
  double energy = 0;
  uint32_t component = 0;
};

// exp(-x) for x >= 0 and log(t) for t in [1, 5], bit for bit what the kernels compute.
double gc_exp_neg(double x);
double gc_log(double t);

std::vector<uint32_t> gc_colours(const RasterImage& image);
uint64_t gc_beta_sum(const std::vector<uint32_t>& colour, uint32_t w, uint32_t h);
// Pixel i's edge d weight (0 past the border).
double gc_smooth(const std::vector<uint32_t>& colour, uint32_t w, uint32_t h, double beta, double gamma, size_t i, int d);
uint64_t gc_smooth_sum(const std::vector<uint32_t>& colour, uint32_t w, uint32_t h, double beta, double gamma);
std::vector<uint32_t> gc_edges(const std::vector<uint32_t>& colour, uint32_t w, uint32_t h, double beta, double gamma,
                               double scale);
GcFit gc_mixture(const GcMixture& m, uint32_t colour);

struct GcData {
  std::vector<double> terms;   // source, sink per pixel (untouched with own_side_only)
  std::vector<uint32_t> comp;  // bits 0-7 background, 8-15 foreground
  uint64_t sum = 0;
};
GcData gc_data(const std::vector<uint32_t>& colour, const std::vector<uint8_t>& labels, std::vector<uint32_t> comp,
               const GcMixture& bg, const GcMixture& fg, double lambda, bool own_side_only);
void gc_terminals(const std::vector<double>& terms, double scale, std::vector<uint32_t>& source,
                  std::vector<uint32_t>& sink);
// 10 sums per side and component (count, z_a, z_a z_b for 00 01 02 11 12 22), background first.
std::vector<uint64_t> gc_moments(const std::vector<uint32_t>& colour, const std::vector<uint8_t>& labels,
                                 const std::vector<uint32_t>& comp);
// One Lloyd step: comp updated, 4 sums per side and centre (count, z_a).
std::vector<uint64_t> gc_kmeans(const std::vector<uint32_t>& colour, const std::vector<uint8_t>& labels,
                                std::vector<uint32_t>& comp, const double (&centres)[2][5][3],
                                const uint32_t (&count)[2]);
// Seeding: a side's d2 (mode 0, 1, 2) and the pixel whose running sum of d2 first passes pick.
std::vector<uint32_t> gc_seed_d2(const std::vector<uint32_t>& colour, const std::vector<uint8_t>& labels, int side,
                                 uint32_t mode, const std::vector<uint32_t>& old, uint32_t centre);
uint32_t gc_seed_find(const std::vector<uint32_t>& d2, uint64_t pick);
// Probable labels from a cut; returns the number changed.
uint64_t gc_labels(std::vector<uint8_t>& labels, const std::vector<uint8_t>& source_side);

}  // namespace mv::ref
