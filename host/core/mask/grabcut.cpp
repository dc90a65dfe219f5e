#include "grabcut.h"

#include <algorithm>
#include <cmath>

#include "gmm.h"
#include "grabcut_kernels.h"
#include "megavox/error.h"

namespace mv::mask {

namespace {

bool is_foreground(uint8_t l) { return l == kForeground || l == kProbableForeground; }

double channel_of(uint32_t colour, int a) { return static_cast<double>((colour >> (8 * a)) & 255u); }

// k-means over each side's labelled pixels on the device (unknown pixels take no part), leaving each pixel's
// cluster as its own side's component: k-means++ seeding (one splitmix64 per side, as one k-means per side
// would draw), then 10 Lloyd steps. Throws when a side has no pixel.
void kmeans_components(GrabCutKernels& gk, GrabCutConsts& consts) {
  SplitMix rng[2];
  uint32_t colour[2] = {0, 0}, found[2] = {0, 0};
  std::vector<uint32_t> centre[2];
  const std::array<uint64_t, 2> count = gk.seed_d2(0, 3, colour);
  if (count[0] == 0 || count[1] == 0)
    throw Error(std::string("grabcut: the start has no ") + (count[1] == 0 ? "foreground" : "background") +
                " pixel to learn from (give a box, strokes of both kinds, or a model)");
  uint64_t pick[2];
  for (int s = 0; s < 2; ++s) pick[s] = std::min(count[s] - 1, static_cast<uint64_t>(rng[s].unit() * double(count[s])));
  gk.seed_find(3, pick, colour);
  for (int s = 0; s < 2; ++s) centre[s].push_back(colour[s]);
  uint32_t seeding = 3;
  std::array<uint64_t, 2> total = gk.seed_d2(1, seeding, colour);
  for (int round = 1; round < kComponents; ++round) {
    for (int s = 0; s < 2; ++s)
      if (total[s] == 0) seeding &= ~(1u << s);  // fewer distinct colours than components
    if (seeding == 0) break;
    for (int s = 0; s < 2; ++s)
      if (seeding & (1u << s))  // the first pixel whose running sum passes the draw (sums are whole numbers)
        pick[s] = std::min(total[s] - 1, static_cast<uint64_t>(std::floor(rng[s].unit() * double(total[s]))));
    gk.seed_find(seeding, pick, colour);
    for (int s = 0; s < 2; ++s)
      if (seeding & (1u << s)) centre[s].push_back(colour[s]);
    (void)found;
    if (round + 1 < kComponents) total = gk.seed_d2(2, seeding, colour);
  }
  double c[2][kComponents][3] = {};
  for (int s = 0; s < 2; ++s)
    for (size_t k = 0; k < centre[s].size(); ++k)
      for (int a = 0; a < 3; ++a) c[s][k][a] = channel_of(centre[s][k], a);
  const uint32_t centres[2] = {uint32_t(centre[0].size()), uint32_t(centre[1].size())};
  for (int iter = 0; iter < 10; ++iter) {
    for (int s = 0; s < 2; ++s)
      for (uint32_t k = 0; k < centres[s]; ++k) consts.set_centre(s, int(k), c[s][k]);
    gk.upload_consts(consts);
    const auto sums = gk.kmeans(centres);
    for (int s = 0; s < 2; ++s)
      for (uint32_t k = 0; k < centres[s]; ++k)
        if (sums[s][k][0] > 0)
          for (int a = 0; a < 3; ++a) c[s][k][a] = double(sums[s][k][1 + a]) / double(sums[s][k][0]);
  }
}

// Fits both mixtures from the device's moments; false when a side has no pixel.
bool learn(GrabCutKernels& gk, GrabCutConsts& consts) {
  const std::array<Moments, 2> m = gk.moments();
  for (int s = 0; s < 2; ++s) {
    uint64_t count = 0;
    for (const auto& k : m[s]) count += k[0];
    if (count == 0) return false;
    consts.set_mixture(s, fit_mixture(m[s]));
  }
  return true;
}

}  // namespace

std::vector<uint8_t> box_labels(uint32_t width, uint32_t height, uint32_t x, uint32_t y, uint32_t w, uint32_t h) {
  if (w == 0 || h == 0 || x >= width || y >= height || w > width - x || h > height - y)
    throw Error("box " + std::to_string(x) + "," + std::to_string(y) + "," + std::to_string(w) + "," +
                std::to_string(h) + " does not lie inside the " + std::to_string(width) + " x " +
                std::to_string(height) + " image");
  std::vector<uint8_t> labels(size_t{width} * height, kBackground);
  for (uint32_t r = y; r < y + h; ++r)
    std::fill_n(labels.begin() + size_t{r} * width + x, w, uint8_t{kProbableForeground});
  return labels;
}

std::vector<uint8_t> labels_to_mask(const std::vector<uint8_t>& labels) {
  std::vector<uint8_t> m(labels.size());
  for (size_t i = 0; i < m.size(); ++i) m[i] = is_foreground(labels[i]) ? 255 : 0;
  return m;
}

GrabCutResult grabcut(Device& dev, const RasterImage& image, const std::vector<uint8_t>& labels,
                      const GrabCutOptions& o, const MinCutFn& cut) {
  for (uint8_t l : labels)
    if (l > kUnknown) throw Error("grabcut: start label " + std::to_string(l) + " (0 to 4)");
  GrabCutKernels gk(dev, image, labels);
  const uint32_t W = gk.width(), H = gk.height();
  const uint64_t n = gk.pixels();
  GrabCutConsts consts;
  // OpenCV's beta: 1 / (2 * mean squared colour difference over the 8-neighbour pairs), 0 for a flat image.
  const uint64_t beta_total = gk.beta_sum();
  const double pairs = double(W - 1) * H + double(W) * (H - 1) + 2.0 * double(W - 1) * double(H - 1);
  consts.v[MV_GC_BETA] = beta_total == 0 || pairs == 0 ? 0.0 : 1.0 / (2.0 * double(beta_total) / pairs);
  consts.v[MV_GC_GAMMA] = o.gamma;
  consts.v[MV_GC_GAMMA_DIAG] = o.gamma / std::sqrt(2.0);
  consts.v[MV_GC_LAMBDA] = o.lambda;
  gk.upload_consts(consts);
  const uint64_t smooth_fx = gk.smooth_sum();

  kmeans_components(gk, consts);
  learn(gk, consts);
  gk.upload_consts(consts);
  gk.data(true);  // each pixel's likeliest component under the k-means mixtures

  GrabCutResult result;
  GridGraph g;
  g.width = W, g.height = H, g.connectivity = 8;
  double scale = 0;
  for (uint32_t iter = 0; iter < std::max<uint32_t>(o.iterations, 1); ++iter) {
    // re-estimate: each pixel to its likeliest component, then learn (OpenCV's order, every iteration)
    if (!learn(gk, consts)) break;  // the last cut took every pixel to one side: nothing to learn
    gk.upload_consts(consts);
    const double total = double(gk.data(false) + smooth_fx) * 0x1p-20;
    // Rounding adds at most 1 per capacity (10 a pixel). The first graph takes half the room, later ones keep
    // its scale while they fit, so their edges stay the first one's.
    const double room = 2147483647.0 - static_cast<double>(n * 10);
    const double old_scale = scale;
    if (scale == 0 || total * scale > room) scale = total > 0 ? std::min(256.0, room / (2 * total)) : 256.0;
    consts.v[MV_GC_SCALE] = scale;
    gk.upload_consts(consts);
    if (scale != old_scale) gk.edges(g.edges);
    gk.terminals(g.source, g.sink);
    const MinCut c = cut(g);
    ++result.iterations;
    result.cut_value = c.value;
    result.scale = scale;
    if (gk.update_labels(c.source_side) == 0) break;
  }
  result.labels = gk.labels();
  return result;
}

}  // namespace mv::mask
