#include "gmm.h"

#include <cmath>
#include <limits>

namespace mv::mask {

namespace {

double dist2(const Colour& a, const Colour& b) {
  const double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
  return x * x + y * y + z * z;
}

// splitmix64: a fixed sequence, so the seeding is the same everywhere (std distributions are not).
struct SplitMix {
  uint64_t s = 0x9e3779b97f4a7c15ull;
  double unit() {  // [0, 1) from the top 53 bits
    uint64_t z = (s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-53;
  }
};

}  // namespace

void Gmm::learn(const std::vector<Colour>& samples, const std::vector<uint8_t>& component) {
  double count[kComponents] = {}, sum[kComponents][3] = {}, prod[kComponents][9] = {};
  for (size_t i = 0; i < samples.size(); ++i) {
    const int k = component[i];
    const Colour& z = samples[i];
    count[k] += 1;
    for (int a = 0; a < 3; ++a) {
      sum[k][a] += z[a];
      for (int b = 0; b < 3; ++b) prod[k][3 * a + b] += z[a] * z[b];
    }
  }
  const double total = static_cast<double>(samples.size());
  for (int k = 0; k < kComponents; ++k) {
    Gaussian& g = g_[k];
    g = Gaussian{};
    if (count[k] == 0) continue;
    g.weight = count[k] / total;
    double c[9];
    for (int a = 0; a < 3; ++a) g.mean[a] = sum[k][a] / count[k];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) c[3 * a + b] = prod[k][3 * a + b] / count[k] - g.mean[a] * g.mean[b];
    auto det3 = [](const double* m) {
      return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) + m[2] * (m[3] * m[7] - m[4] * m[6]);
    };
    double det = det3(c);
    if (det <= std::numeric_limits<double>::epsilon()) {  // singular (flat colour, grey images): OpenCV's fix
      c[0] += 0.01, c[4] += 0.01, c[8] += 0.01;
      det = det3(c);
    }
    g.det = det;
    g.factor = g.weight / std::sqrt(det);
    g.inverse[0] = (c[4] * c[8] - c[5] * c[7]) / det;
    g.inverse[1] = (c[2] * c[7] - c[1] * c[8]) / det;
    g.inverse[2] = (c[1] * c[5] - c[2] * c[4]) / det;
    g.inverse[3] = (c[5] * c[6] - c[3] * c[8]) / det;
    g.inverse[4] = (c[0] * c[8] - c[2] * c[6]) / det;
    g.inverse[5] = (c[2] * c[3] - c[0] * c[5]) / det;
    g.inverse[6] = (c[3] * c[7] - c[4] * c[6]) / det;
    g.inverse[7] = (c[1] * c[6] - c[0] * c[7]) / det;
    g.inverse[8] = (c[0] * c[4] - c[1] * c[3]) / det;
  }
}

double Gmm::component_density(int k, const Colour& z) const {
  const Gaussian& g = g_[k];
  if (g.weight == 0) return 0;
  const double d[3] = {z[0] - g.mean[0], z[1] - g.mean[1], z[2] - g.mean[2]};
  double m = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) m += d[a] * g.inverse[3 * a + b] * d[b];
  return g.factor * std::exp(-0.5 * m);
}

int Gmm::component_of(const Colour& z) const { return fit(z).component; }

Gmm::Fit Gmm::fit(const Colour& z) const {
  Fit f{0, 0};
  double top = -1;
  for (int k = 0; k < kComponents; ++k) {
    const double p = component_density(k, z);
    f.density += p;
    if (p > top) top = p, f.component = k;
  }
  return f;
}

std::vector<uint8_t> kmeans_components(const std::vector<Colour>& samples) {
  const size_t n = samples.size();
  std::vector<uint8_t> label(n, 0);
  if (n == 0) return label;
  constexpr int K = Gmm::kComponents;
  SplitMix rng;
  std::vector<Colour> centre;
  centre.push_back(samples[std::min(n - 1, static_cast<size_t>(rng.unit() * n))]);
  std::vector<double> d2(n);
  for (size_t i = 0; i < n; ++i) d2[i] = dist2(samples[i], centre[0]);
  while (centre.size() < K) {  // k-means++: the next centre drawn with probability proportional to d^2
    double total = 0;
    for (double v : d2) total += v;
    if (total == 0) break;  // fewer distinct colours than components
    const double pick = rng.unit() * total;
    double acc = 0;
    size_t chosen = n - 1;
    for (size_t i = 0; i < n; ++i)
      if ((acc += d2[i]) > pick) {
        chosen = i;
        break;
      }
    centre.push_back(samples[chosen]);
    for_each_sample(n, [&](size_t i) { d2[i] = std::min(d2[i], dist2(samples[i], centre.back())); });
  }
  for (int iter = 0; iter < 10; ++iter) {
    for_each_sample(n, [&](size_t i) {
      int best = 0;
      double bd = dist2(samples[i], centre[0]);
      for (size_t k = 1; k < centre.size(); ++k) {
        const double d = dist2(samples[i], centre[k]);
        if (d < bd) bd = d, best = static_cast<int>(k);
      }
      label[i] = static_cast<uint8_t>(best);
    });
    std::vector<Colour> sum(centre.size(), Colour{});
    std::vector<double> count(centre.size(), 0);
    for (size_t i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) sum[label[i]][a] += samples[i][a];
      count[label[i]] += 1;
    }
    for (size_t k = 0; k < centre.size(); ++k)
      if (count[k] > 0)
        for (int a = 0; a < 3; ++a) centre[k][a] = sum[k][a] / count[k];
  }
  return label;
}

}  // namespace mv::mask
