#include "grabcut_reference.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mv::ref {

namespace {

constexpr int kRefDx[8] = {1, -1, 0, 0, 1, -1, 1, -1};
constexpr int kRefDy[8] = {0, 0, 1, -1, 1, -1, -1, 1};

int side_of(uint8_t l) { return l == 4 ? -1 : (l == 1 || l == 3) ? 1 : 0; }

double ch(uint32_t c, int a) { return double((c >> (8 * a)) & 255u); }

uint32_t sq_dist(uint32_t a, uint32_t b) {
  uint32_t s = 0;
  for (int k = 0; k < 3; ++k) {
    const int d = int((a >> (8 * k)) & 255u) - int((b >> (8 * k)) & 255u);
    s += uint32_t(d * d);
  }
  return s;
}

uint64_t fixed20(double v) { return uint64_t(std::llround(v * 1048576.0)); }

}  // namespace

double gc_exp_neg(double x) {
  if (!(x < 707.0)) return 0.0;
  const double hi = 0x1.62e42fee00000p-1 / 16, lo = 0x1.a39ef35793c76p-33 / 16;  // fdlibm's ln2_hi, ln2_lo
  const double t = std::floor(x * (16 / std::log(2.0)));
  const double r = (x - t * hi) - t * lo;
  double coef[11];
  double f = 1;
  for (int i = 0; i <= 10; ++i) coef[i] = (i % 2 == 0 ? 1.0 : -1.0) / (f *= (i == 0 ? 1 : i));
  double p = coef[10];
  for (int i = 9; i >= 0; --i) p = p * r + coef[i];
  const long k = long(t);
  return std::ldexp(p * std::exp2(-double(k % 16) / 16.0), -int(k / 16));
}

double gc_log(double t) {
  const int j = int(std::clamp(std::floor((t - 1.0) * 32.0), 0.0, 128.0));
  const double c = 1.0 + j / 32.0, u = (t - c) * (1 / c);
  double p = -1.0 / 12;  // log1p(u) = u (1 - u / 2 + u^2 / 3 - ... - u^11 / 12)
  for (int i = 11; i >= 1; --i) p = p * u + (i % 2 == 1 ? 1.0 : -1.0) / i;
  return std::log(c) + u * p;
}

std::vector<uint32_t> gc_colours(const RasterImage& image) {
  const size_t n = size_t{image.width} * image.height;
  const uint32_t top = std::max<uint32_t>(image.max_value, 1);
  std::vector<uint32_t> out(n);
  for (size_t i = 0; i < n; ++i)
    for (uint32_t a = 0; a < 3; ++a) {
      const uint32_t v = std::min<uint32_t>(image.samples[i * image.channels + (image.channels == 3 ? a : 0)], top);
      out[i] |= ((v * 255 + top / 2) / top) << (8 * a);
    }
  return out;
}

uint64_t gc_beta_sum(const std::vector<uint32_t>& colour, uint32_t w, uint32_t h) {
  uint64_t s = 0;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      if (x + 1 < w) s += sq_dist(colour[y * w + x], colour[y * w + x + 1]);
      if (y + 1 < h) s += sq_dist(colour[y * w + x], colour[(y + 1) * w + x]);
      if (x + 1 < w && y + 1 < h) s += sq_dist(colour[y * w + x], colour[(y + 1) * w + x + 1]);
      if (x + 1 < w && y > 0) s += sq_dist(colour[y * w + x], colour[(y - 1) * w + x + 1]);
    }
  return s;
}

double gc_smooth(const std::vector<uint32_t>& colour, uint32_t w, uint32_t h, double beta, double gamma, size_t i, int d) {
  const long x = long(i % w) + kRefDx[d], y = long(i / w) + kRefDy[d];
  if (x < 0 || y < 0 || x >= long(w) || y >= long(h)) return 0;
  const double g = d < 4 ? gamma : gamma / std::sqrt(2.0);
  return g * gc_exp_neg(beta * double(sq_dist(colour[i], colour[size_t(y) * w + size_t(x)])));
}

uint64_t gc_smooth_sum(const std::vector<uint32_t>& colour, uint32_t w, uint32_t h, double beta, double gamma) {
  uint64_t s = 0;
  for (size_t i = 0; i < colour.size(); ++i)
    for (int d = 0; d < 8; ++d) s += fixed20(gc_smooth(colour, w, h, beta, gamma, i, d));
  return s;
}

std::vector<uint32_t> gc_edges(const std::vector<uint32_t>& colour, uint32_t w, uint32_t h, double beta, double gamma,
                               double scale) {
  std::vector<uint32_t> e(colour.size() * 8);
  for (size_t i = 0; i < colour.size(); ++i)
    for (int d = 0; d < 8; ++d) e[i * 8 + d] = uint32_t(std::llround(gc_smooth(colour, w, h, beta, gamma, i, d) * scale));
  return e;
}

GcFit gc_mixture(const GcMixture& m, uint32_t colour) {
  double e[5] = {};
  int best = -1;
  for (int k = 0; k < 5; ++k) {
    if (!m[k].present) continue;
    const double d[3] = {ch(colour, 0) - m[k].mean[0], ch(colour, 1) - m[k].mean[1], ch(colour, 2) - m[k].mean[2]};
    double maha = 0;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) maha += d[a] * m[k].inverse[3 * a + b] * d[b];
    e[k] = 0.5 * maha + m[k].energy;
    if (best < 0 || e[k] < e[best]) best = k;
  }
  if (best < 0 || !(e[best] < -std::log(std::numeric_limits<double>::denorm_min()))) return {690.8, 0};
  double s = 0;
  for (int k = 0; k < 5; ++k)
    if (k != best && m[k].present && e[k] - e[best] < 40.0) s += gc_exp_neg(e[k] - e[best]);  // exp(-40) < 5e-18
  const double v = e[best] - gc_log(1.0 + s);
  return {v >= -std::log(1e-300) ? 690.8 : v, uint32_t(best)};
}

GcData gc_data(const std::vector<uint32_t>& colour, const std::vector<uint8_t>& labels, std::vector<uint32_t> comp,
               const GcMixture& bg, const GcMixture& fg, double lambda, bool own_side_only) {
  GcData out;
  out.terms.assign(colour.size() * 2, 0.0);
  for (size_t i = 0; i < colour.size(); ++i) {
    const uint8_t l = labels[i];
    const int side = side_of(l);
    double s, t;
    if (own_side_only || l <= 1) {
      if (side < 0) continue;
      const GcFit f = gc_mixture(side ? fg : bg, colour[i]);
      comp[i] = side ? (comp[i] & 0xffff00ffu) | (f.component << 8) : (comp[i] & 0xffffff00u) | f.component;
      s = l == 1 ? lambda : 0;
      t = l == 0 ? lambda : 0;
    } else {
      const GcFit b = gc_mixture(bg, colour[i]), f = gc_mixture(fg, colour[i]);
      comp[i] = b.component | (f.component << 8);
      s = b.energy, t = f.energy;
    }
    if (own_side_only) continue;
    const double common = std::min(s, t);
    out.terms[2 * i] = s - common;
    out.terms[2 * i + 1] = t - common;
    out.sum += fixed20(s - common) + fixed20(t - common);
  }
  out.comp = std::move(comp);
  return out;
}

void gc_terminals(const std::vector<double>& terms, double scale, std::vector<uint32_t>& source,
                  std::vector<uint32_t>& sink) {
  const size_t n = terms.size() / 2;
  source.resize(n), sink.resize(n);
  for (size_t i = 0; i < n; ++i) {
    source[i] = uint32_t(std::llround(terms[2 * i] * scale));
    sink[i] = uint32_t(std::llround(terms[2 * i + 1] * scale));
  }
}

std::vector<uint64_t> gc_moments(const std::vector<uint32_t>& colour, const std::vector<uint8_t>& labels,
                                 const std::vector<uint32_t>& comp) {
  std::vector<uint64_t> m(100, 0);
  for (size_t i = 0; i < colour.size(); ++i) {
    const int side = side_of(labels[i]);
    if (side < 0) continue;
    uint64_t* at = &m[10 * (5 * side + ((comp[i] >> (8 * side)) & 255u))];
    const uint64_t z[3] = {colour[i] & 255u, (colour[i] >> 8) & 255u, (colour[i] >> 16) & 255u};
    at[0] += 1;
    for (int a = 0; a < 3; ++a) at[1 + a] += z[a];
    at[4] += z[0] * z[0], at[5] += z[0] * z[1], at[6] += z[0] * z[2];
    at[7] += z[1] * z[1], at[8] += z[1] * z[2], at[9] += z[2] * z[2];
  }
  return m;
}

std::vector<uint64_t> gc_kmeans(const std::vector<uint32_t>& colour, const std::vector<uint8_t>& labels,
                                std::vector<uint32_t>& comp, const double (&centres)[2][5][3],
                                const uint32_t (&count)[2]) {
  std::vector<uint64_t> sums(40, 0);
  for (size_t i = 0; i < colour.size(); ++i) {
    const int side = side_of(labels[i]);
    if (side < 0) continue;
    uint32_t best = 0;
    double bd = 0;
    for (uint32_t k = 0; k < count[side]; ++k) {
      const double x = ch(colour[i], 0) - centres[side][k][0], y = ch(colour[i], 1) - centres[side][k][1],
                   z = ch(colour[i], 2) - centres[side][k][2];
      const double d = x * x + y * y + z * z;
      if (k == 0 || d < bd) bd = d, best = k;
    }
    comp[i] = side ? (comp[i] & 0xffff00ffu) | (best << 8) : (comp[i] & 0xffffff00u) | best;
    uint64_t* at = &sums[4 * (5 * side + best)];
    at[0] += 1;
    for (int a = 0; a < 3; ++a) at[1 + a] += (colour[i] >> (8 * a)) & 255u;
  }
  return sums;
}

std::vector<uint32_t> gc_seed_d2(const std::vector<uint32_t>& colour, const std::vector<uint8_t>& labels, int side,
                                 uint32_t mode, const std::vector<uint32_t>& old, uint32_t centre) {
  std::vector<uint32_t> d2(colour.size(), 0);
  for (size_t i = 0; i < colour.size(); ++i) {
    if (side_of(labels[i]) != side) continue;
    d2[i] = mode == 0 ? 1 : mode == 1 ? sq_dist(colour[i], centre) : std::min(old[i], sq_dist(colour[i], centre));
  }
  return d2;
}

uint32_t gc_seed_find(const std::vector<uint32_t>& d2, uint64_t pick) {
  uint64_t acc = 0;
  for (size_t i = 0; i < d2.size(); ++i)
    if ((acc += d2[i]) > pick) return uint32_t(i);
  return uint32_t(d2.size());
}

uint64_t gc_labels(std::vector<uint8_t>& labels, const std::vector<uint8_t>& source_side) {
  uint64_t changed = 0;
  for (size_t i = 0; i < labels.size(); ++i) {
    if (labels[i] <= 1) continue;
    const uint8_t l = source_side[i] ? 3 : 2;
    changed += l != labels[i];
    labels[i] = l;
  }
  return changed;
}

}  // namespace mv::ref
