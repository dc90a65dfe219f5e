#include "grabcut.h"

#include <algorithm>
#include <cmath>

#include "gmm.h"
#include "megavox/error.h"

namespace mv::mask {

namespace {

// Neighbour d's offset (the numbering of include/megavox/grid_graph.h); even d are the pairs counted once.
constexpr int kDx[8] = {1, -1, 0, 0, 1, -1, 1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, -1, 1};

bool is_foreground(uint8_t l) { return l == kForeground || l == kProbableForeground; }
bool is_hard(uint8_t l) { return l == kForeground || l == kBackground; }

double colour_dist2(const Colour& a, const Colour& b) {
  const double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
  return x * x + y * y + z * z;
}

// -log of a density, finite where the density underflows.
double neg_log(double p) { return p > 1e-300 ? -std::log(p) : 690.8; }

}  // namespace

std::vector<Colour> image_colours(const RasterImage& image) {
  const size_t n = size_t{image.width} * image.height;
  if (image.channels != 1 && image.channels != 3) throw Error("grabcut: images have 1 or 3 channels");
  if (image.samples.size() != n * image.channels) throw Error("grabcut: the image's samples do not match its size");
  std::vector<Colour> c(n);
  const double to255 = 255.0 / std::max<uint32_t>(image.max_value, 1);
  for (size_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) c[i][a] = image.samples[i * image.channels + (image.channels == 3 ? a : 0)] * to255;
  return c;
}

double smoothness_beta(const std::vector<Colour>& c, uint32_t w, uint32_t h) {
  double total = 0, pairs = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x)
      for (int d = 0; d < 8; d += 2) {
        const long nx = long{x} + kDx[d], ny = long{y} + kDy[d];
        if (nx < 0 || ny < 0 || nx >= long{w} || ny >= long{h}) continue;
        total += colour_dist2(c[size_t{y} * w + x], c[size_t(ny) * w + size_t(nx)]);
        pairs += 1;
      }
  return total <= 1e-12 || pairs == 0 ? 0.0 : 1.0 / (2.0 * total / pairs);
}

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

GrabCutResult grabcut(const RasterImage& image, std::vector<uint8_t> labels, const GrabCutOptions& o,
                      const MinCutFn& cut) {
  const uint32_t W = image.width, H = image.height;
  const size_t n = size_t{W} * H;
  if (labels.size() != n) throw Error("grabcut: the start labels do not match the image");
  const std::vector<Colour> colours = image_colours(image);
  const double beta = smoothness_beta(colours, W, H);

  // Smoothness weights do not change between iterations: one double per (pixel, d), each pair's weight
  // computed from both ends alike.
  std::vector<double> smooth(n * 8, 0.0);
  for_each_sample(n, [&](size_t i) {
    const long x = long(i % W), y = long(i / W);
    for (int d = 0; d < 8; ++d) {
      const long nx = x + kDx[d], ny = y + kDy[d];
      if (nx < 0 || ny < 0 || nx >= long{W} || ny >= long{H}) continue;
      const size_t j = size_t(ny) * W + size_t(nx), a = d % 2 == 0 ? i : j, b = d % 2 == 0 ? j : i;
      const double gamma = d < 4 ? o.gamma : o.gamma / std::sqrt(2.0);
      smooth[i * 8 + d] = gamma * std::exp(-beta * colour_dist2(colours[a], colours[b]));
    }
  });

  // Mixtures from k-means over the labelled pixels of each side (unknown pixels take no part).
  Gmm fg, bg;
  {
    std::vector<Colour> fs, bs;
    for (size_t i = 0; i < n; ++i) {
      if (labels[i] == kUnknown) continue;
      (is_foreground(labels[i]) ? fs : bs).push_back(colours[i]);
    }
    if (fs.empty() || bs.empty())
      throw Error(std::string("grabcut: the start has no ") + (fs.empty() ? "foreground" : "background") +
                  " pixel to learn from (give a box, strokes of both kinds, or a model)");
    fg.learn(fs, kmeans_components(fs));
    bg.learn(bs, kmeans_components(bs));
  }

  GrabCutResult result;
  std::vector<Colour> fs, bs;
  std::vector<uint8_t> fk, bk;
  std::vector<double> source(n), sink(n);
  // Each pixel's likeliest component under the current mixtures, in either (a hard label needs its own side's
  // only). Found with the data terms, which evaluate the same mixtures; first from the k-means mixtures.
  std::vector<uint8_t> fg_component(n), bg_component(n);
  auto own_side_component = [&](size_t i) {
    if (is_foreground(labels[i])) fg_component[i] = static_cast<uint8_t>(fg.component_of(colours[i]));
    else bg_component[i] = static_cast<uint8_t>(bg.component_of(colours[i]));
  };
  for_each_sample(n, [&](size_t i) {
    if (labels[i] != kUnknown) own_side_component(i);
  });
  double scale = 0;
  for (uint32_t iter = 0; iter < std::max<uint32_t>(o.iterations, 1); ++iter) {
    {  // re-estimate: each pixel to its likeliest component, then learn (OpenCV's order, every iteration)
      fs.clear(), bs.clear(), fk.clear(), bk.clear();
      for (size_t i = 0; i < n; ++i) {
        if (labels[i] == kUnknown) continue;
        if (is_foreground(labels[i])) {
          fs.push_back(colours[i]);
          fk.push_back(fg_component[i]);
        } else {
          bs.push_back(colours[i]);
          bk.push_back(bg_component[i]);
        }
      }
      if (fs.empty() || bs.empty()) break;  // the last cut took every pixel to one side: nothing to learn
      fg.learn(fs, fk);
      bg.learn(bs, bk);
    }
    // Data terms; hard labels get lambda toward their side.
    for_each_sample(n, [&](size_t i) {
      double s, t;
      if (is_hard(labels[i])) {
        s = labels[i] == kForeground ? o.lambda : 0;
        t = labels[i] == kForeground ? 0 : o.lambda;
        own_side_component(i);
      } else {
        const Gmm::Fit f = fg.fit(colours[i]), b = bg.fit(colours[i]);
        s = neg_log(b.density), t = neg_log(f.density);
        fg_component[i] = static_cast<uint8_t>(f.component);
        bg_component[i] = static_cast<uint8_t>(b.component);
      }
      const double common = std::min(s, t);
      source[i] = s - common;
      sink[i] = t - common;
    });
    double total = 0;
    for (size_t i = 0; i < n; ++i) total += source[i] + sink[i];
    for (double v : smooth) total += v;
    // Rounding adds at most 1 per capacity (10 a pixel). The first graph takes half the room, later ones keep
    // its scale while they fit, so their edges stay the first one's.
    const double room = 2147483647.0 - static_cast<double>(n * 10);
    if (scale == 0 || total * scale > room) scale = total > 0 ? std::min(256.0, room / (2 * total)) : 256.0;
    GridGraph g;
    g.width = W, g.height = H, g.connectivity = 8;
    g.source.resize(n), g.sink.resize(n), g.edges.resize(n * 8);
    for_each_sample(n, [&](size_t i) {
      g.source[i] = static_cast<uint32_t>(std::llround(source[i] * scale));
      g.sink[i] = static_cast<uint32_t>(std::llround(sink[i] * scale));
      for (size_t k = i * 8; k < i * 8 + 8; ++k) g.edges[k] = static_cast<uint32_t>(std::llround(smooth[k] * scale));
    });
    const MinCut c = cut(g);
    ++result.iterations;
    result.cut_value = c.value;
    result.scale = scale;
    bool changed = false;
    for (size_t i = 0; i < n; ++i) {
      if (is_hard(labels[i])) continue;
      const uint8_t l = c.source_side[i] ? kProbableForeground : kProbableBackground;
      changed |= l != labels[i];
      labels[i] = l;
    }
    if (!changed) break;
  }
  result.labels = std::move(labels);
  return result;
}

}  // namespace mv::mask
