// Colour quantization by weighted k-means in CIELAB (megavox/colour_quantize.h).
#include "megavox/colour_quantize.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cmath>
#include <numeric>
#include <queue>
#include <string>
#include <utility>

#include "megavox/error.h"

namespace mv {
namespace {

using Lab = std::array<double, 3>;
constexpr uint32_t kQuantizeIterations = 10;  // Lloyd rounds at most; most runs settle sooner

double quantize_linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }
double quantize_gamma(double c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055; }
constexpr double kDelta = 6.0 / 29.0, kWhite[3] = {0.95047, 1.0, 1.08883};
double lab_f(double t) { return t > kDelta * kDelta * kDelta ? std::cbrt(t) : t / (3 * kDelta * kDelta) + 4.0 / 29.0; }
double lab_finv(double f) { return f > kDelta ? f * f * f : 3 * kDelta * kDelta * (f - 4.0 / 29.0); }

std::array<uint8_t, 3> lab_to_srgb(const Lab& lab) {
  const double fy = (lab[0] + 16) / 116, fx = fy + lab[1] / 500, fz = fy - lab[2] / 200;
  const double x = kWhite[0] * lab_finv(fx), y = kWhite[1] * lab_finv(fy), z = kWhite[2] * lab_finv(fz);
  const double lin[3] = {3.2404542 * x - 1.5371385 * y - 0.4985314 * z, -0.9692660 * x + 1.8760108 * y + 0.0415560 * z,
                         0.0556434 * x - 0.2040259 * y + 1.0572252 * z};
  std::array<uint8_t, 3> out{};
  for (int c = 0; c < 3; ++c)
    out[c] = static_cast<uint8_t>(std::lround(std::clamp(quantize_gamma(std::clamp(lin[c], 0.0, 1.0)) * 255.0, 0.0, 255.0)));
  return out;
}

double lab_distance2(const Lab& a, const Lab& b) {
  const double d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];
  return d0 * d0 + d1 * d1 + d2 * d2;
}

void build_tree(const std::vector<Lab>& c, std::vector<uint32_t>& order, size_t lo, size_t hi, int axis) {
  if (hi - lo <= 1) return;
  const size_t mid = lo + (hi - lo) / 2;
  std::nth_element(order.begin() + lo, order.begin() + mid, order.begin() + hi, [&](uint32_t a, uint32_t b) {
    return c[a][axis] != c[b][axis] ? c[a][axis] < c[b][axis] : a < b;
  });
  build_tree(c, order, lo, mid, (axis + 1) % 3);
  build_tree(c, order, mid + 1, hi, (axis + 1) % 3);
}

// Nearest centre by the k-d tree of centre_tree_order (split at the median by (value, index), so the tree and
// every answer are the same whatever the standard library's partition does); ties go to the lower centre.
class CentreTree {
 public:
  CentreTree(const std::vector<Lab>& centres, const std::vector<uint32_t>& order) : c_(centres), order_(order) {}
  // `guess`: a centre to start from (the last round's): the search prunes from its distance at once, and the
  // answer is the same as from nothing (the nearest, the lowest of equals).
  uint32_t nearest(const Lab& q, uint32_t guess) const {
    uint32_t best = guess;
    double d = lab_distance2(c_[guess], q);
    search(0, order_.size(), 0, q, best, d);
    return best;
  }

 private:
  void search(size_t lo, size_t hi, int axis, const Lab& q, uint32_t& best, double& d) const {
    if (lo >= hi) return;
    const size_t mid = lo + (hi - lo) / 2;
    const uint32_t at = order_[mid];
    const double here = lab_distance2(c_[at], q);
    if (here < d || (here == d && at < best)) best = at, d = here;
    const double diff = q[axis] - c_[at][axis];
    const int next = (axis + 1) % 3;
    if (diff < 0) {
      search(lo, mid, next, q, best, d);
      if (diff * diff <= d) search(mid + 1, hi, next, q, best, d);
    } else {
      search(mid + 1, hi, next, q, best, d);
      if (diff * diff <= d) search(lo, mid, next, q, best, d);
    }
  }
  const std::vector<Lab>& c_;
  const std::vector<uint32_t>& order_;
};

struct QuantizeBox {
  double spread;  // weighted sum of squared distances to the box's mean
  size_t lo, hi;
  int axis;       // of the largest weighted variance
  bool operator<(const QuantizeBox& o) const { return spread != o.spread ? spread < o.spread : lo > o.lo; }
};

// An order-preserving 64-bit key of a finite double (-0 as +0), for sorting by value with the index as tie-break.
uint64_t sortable(double v) {
  const uint64_t b = std::bit_cast<uint64_t>(v == 0 ? 0.0 : v);
  return b >> 63 ? ~b : b | (uint64_t{1} << 63);
}

// Splits `a` ((value key, colour) pairs, a strict order) at its weighted median: returns m, 1 <= m < a.size(),
// the fewest smallest pairs whose weight reaches half the total (at most all but one), and leaves those m first.
// A quickselect: each round keeps the side holding that point, so it costs about what two passes over `a` do,
// where sorting the box at every split made the median cut most of the quantizer's time.
size_t weighted_median_split(std::vector<std::pair<uint64_t, uint32_t>>& a, const std::vector<uint64_t>& w) {
  double total = 0;
  for (const auto& x : a) total += double(w[x.second]);
  const double half = total / 2;
  double before = 0;  // the weight of a[0, lo): all smaller than a[lo, hi)
  size_t lo = 0, hi = a.size();
  while (hi - lo > 16) {
    const size_t mid = lo + (hi - lo) / 2;  // median of three: some element is below it, and it is not below itself
    if (a[mid] < a[lo]) std::swap(a[mid], a[lo]);
    if (a[hi - 1] < a[mid]) std::swap(a[hi - 1], a[mid]);
    if (a[mid] < a[lo]) std::swap(a[mid], a[lo]);
    const std::pair<uint64_t, uint32_t> pivot = a[mid];
    const size_t p = static_cast<size_t>(
        std::partition(a.begin() + lo, a.begin() + hi, [&](const auto& x) { return x < pivot; }) - a.begin());
    double left = 0;
    for (size_t i = lo; i < p; ++i) left += double(w[a[i].second]);
    if (before + left >= half) {
      hi = p;
    } else {
      before += left;
      lo = p;
    }
  }
  std::sort(a.begin() + lo, a.begin() + hi);
  size_t m = a.size() - 1;
  for (size_t i = lo; i < hi; ++i) {
    before += double(w[a[i].second]);
    if (before >= half) {
      m = std::min(i + 1, a.size() - 1);
      break;
    }
  }
  return std::max<size_t>(m, 1);
}

// Median cut over the colours' order `idx`: `k` boxes (ranges of idx), split where the weighted spread is
// largest, along the axis of largest weighted variance, at the weighted median.
std::vector<std::pair<size_t, size_t>> median_cut(const std::vector<Lab>& lab, const std::vector<uint64_t>& w,
                                                  std::vector<uint32_t>& idx, size_t k) {
  auto box = [&](size_t lo, size_t hi) {
    double sw = 0, m[3] = {}, v[3] = {};
    for (size_t i = lo; i < hi; ++i) {
      sw += double(w[idx[i]]);
      for (int a = 0; a < 3; ++a) m[a] += double(w[idx[i]]) * lab[idx[i]][a];
    }
    for (double& x : m) x /= sw;
    for (size_t i = lo; i < hi; ++i)
      for (int a = 0; a < 3; ++a) v[a] += double(w[idx[i]]) * (lab[idx[i]][a] - m[a]) * (lab[idx[i]][a] - m[a]);
    return QuantizeBox{hi - lo > 1 ? v[0] + v[1] + v[2] : 0.0, lo, hi, int(std::max_element(v, v + 3) - v)};
  };
  std::priority_queue<QuantizeBox> boxes;
  std::vector<std::pair<size_t, size_t>> done;
  std::vector<std::pair<uint64_t, uint32_t>> keyed;  // a box's (value on its axis, index)
  boxes.push(box(0, idx.size()));
  while (!boxes.empty() && boxes.size() + done.size() < k) {
    const QuantizeBox b = boxes.top();
    boxes.pop();
    if (b.spread <= 0) {
      done.push_back({b.lo, b.hi});
      continue;
    }
    keyed.resize(b.hi - b.lo);
    for (size_t i = b.lo; i < b.hi; ++i) keyed[i - b.lo] = {sortable(lab[idx[i]][b.axis]), idx[i]};
    const size_t cut = b.lo + weighted_median_split(keyed, w);
    for (size_t i = b.lo; i < b.hi; ++i) idx[i] = keyed[i - b.lo].second;
    boxes.push(box(b.lo, cut));
    boxes.push(box(cut, b.hi));
  }
  for (; !boxes.empty(); boxes.pop()) done.push_back({boxes.top().lo, boxes.top().hi});
  return done;
}

}  // namespace

std::array<double, 3> srgb_to_lab(const uint8_t rgb[3]) {
  const double r = quantize_linear(rgb[0] / 255.0), g = quantize_linear(rgb[1] / 255.0), b = quantize_linear(rgb[2] / 255.0);
  const double x = 0.4124564 * r + 0.3575761 * g + 0.1804375 * b;
  const double y = 0.2126729 * r + 0.7151522 * g + 0.0721750 * b;
  const double z = 0.0193339 * r + 0.1191920 * g + 0.9503041 * b;
  const double fx = lab_f(x / kWhite[0]), fy = lab_f(y / kWhite[1]), fz = lab_f(z / kWhite[2]);
  return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

double delta_e94(const std::array<double, 3>& ref, const std::array<double, 3>& lab) {
  const double dl = ref[0] - lab[0], da = ref[1] - lab[1], db = ref[2] - lab[2];
  const double c1 = std::hypot(ref[1], ref[2]), c2 = std::hypot(lab[1], lab[2]), dc = c1 - c2;
  const double dh2 = std::max(0.0, da * da + db * db - dc * dc);
  const double sc = 1 + 0.045 * c1, sh = 1 + 0.015 * c1;
  return std::sqrt(dl * dl + (dc / sc) * (dc / sc) + dh2 / (sh * sh));
}

bool nearest_centres_on_host(const std::vector<Lab>& lab, const std::vector<Lab>& centre,
                             const std::vector<uint32_t>& order, std::vector<uint32_t>& cluster) {
  const CentreTree tree(centre, order);
  std::atomic<bool> changed = false;  // each colour's answer is its own: the same whatever the threads do
  tbb::parallel_for(tbb::blocked_range<size_t>(0, lab.size(), 4096), [&](const tbb::blocked_range<size_t>& range) {
    bool moved = false;
    for (size_t u = range.begin(); u < range.end(); ++u) {
      const uint32_t c = tree.nearest(lab[u], cluster[u]);
      moved = moved || c != cluster[u];
      cluster[u] = c;
    }
    if (moved) changed = true;
  });
  return changed;
}

std::vector<uint32_t> centre_tree_order(const std::vector<Lab>& centres) {
  std::vector<uint32_t> order(centres.size());
  std::iota(order.begin(), order.end(), 0u);
  build_tree(centres, order, 0, order.size(), 0);
  return order;
}

ColourQuantizeReport quantize_colours(std::vector<uint8_t>& rgb, uint32_t bits, const NearestCentres& nearest) {
  if (bits < 1 || bits > 24) throw Error("--colour-bits " + std::to_string(bits) + ": 1 to 24 bits");
  const auto t0 = std::chrono::steady_clock::now();
  ColourQuantizeReport r;
  r.bits = bits;
  const size_t n = rgb.size() / 3;
  std::vector<uint32_t> packed(n);
  for (size_t i = 0; i < n; ++i) packed[i] = uint32_t{rgb[3 * i]} << 16 | uint32_t{rgb[3 * i + 1]} << 8 | rgb[3 * i + 2];
  std::vector<uint32_t> colours = packed;
  tbb::parallel_sort(colours.begin(), colours.end());
  colours.erase(std::unique(colours.begin(), colours.end()), colours.end());
  r.colours_in = r.colours_out = colours.size();
  const size_t k = size_t{1} << bits;
  if (bits == 24 || colours.size() <= k) {
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return r;
  }
  std::vector<uint32_t> slot(n);
  std::vector<uint64_t> w(colours.size(), 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t i = range.begin(); i < range.end(); ++i)
      slot[i] = static_cast<uint32_t>(std::lower_bound(colours.begin(), colours.end(), packed[i]) - colours.begin());
  });
  for (size_t i = 0; i < n; ++i) ++w[slot[i]];
  std::vector<Lab> lab(colours.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, colours.size(), 4096), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t u = range.begin(); u < range.end(); ++u) {
      const uint8_t c[3] = {uint8_t(colours[u] >> 16), uint8_t(colours[u] >> 8), uint8_t(colours[u])};
      lab[u] = srgb_to_lab(c);
    }
  });
  std::vector<uint32_t> idx(colours.size());
  std::iota(idx.begin(), idx.end(), 0u);
  const auto boxes = median_cut(lab, w, idx, k);
  std::vector<uint32_t> cluster(colours.size());
  for (size_t b = 0; b < boxes.size(); ++b)
    for (size_t i = boxes[b].first; i < boxes[b].second; ++i) cluster[idx[i]] = static_cast<uint32_t>(b);
  std::vector<Lab> centre(boxes.size());
  auto update_centres = [&] {
    std::vector<Lab> sum(centre.size(), Lab{});
    std::vector<double> sw(centre.size(), 0);
    for (size_t u = 0; u < colours.size(); ++u) {
      for (int a = 0; a < 3; ++a) sum[cluster[u]][a] += double(w[u]) * lab[u][a];
      sw[cluster[u]] += double(w[u]);
    }
    for (size_t c = 0; c < centre.size(); ++c)
      if (sw[c] > 0)
        for (int a = 0; a < 3; ++a) centre[c][a] = sum[c][a] / sw[c];
  };
  update_centres();
  for (r.iterations = 0; r.iterations < kQuantizeIterations;) {
    ++r.iterations;
    const std::vector<uint32_t> order = centre_tree_order(centre);
    if (!(nearest ? nearest(lab, centre, order, cluster) : nearest_centres_on_host(lab, centre, order, cluster))) break;
    update_centres();
  }
  std::vector<std::array<uint8_t, 3>> out(centre.size());
  for (size_t c = 0; c < centre.size(); ++c) out[c] = lab_to_srgb(centre[c]);
  std::vector<uint32_t> seen;
  std::vector<double> delta(colours.size());
  std::vector<std::array<int, 3>> err(colours.size());
  std::vector<Lab> out_lab(out.size());
  for (size_t c = 0; c < out.size(); ++c) out_lab[c] = srgb_to_lab(out[c].data());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, colours.size(), 4096), [&](const tbb::blocked_range<size_t>& range) {
    for (size_t u = range.begin(); u < range.end(); ++u) {
      const auto& q = out[cluster[u]];
      for (int a = 0; a < 3; ++a) err[u][a] = std::abs(int(q[a]) - int(colours[u] >> (16 - 8 * a) & 255));
      delta[u] = delta_e94(lab[u], out_lab[cluster[u]]);
    }
  });
  std::vector<char> used(out.size(), 0);  // a cluster left empty by the last round has no entries
  for (size_t u = 0; u < colours.size(); ++u) used[cluster[u]] = 1;
  for (size_t c = 0; c < out.size(); ++c)
    if (used[c]) seen.push_back(uint32_t{out[c][0]} << 16 | uint32_t{out[c][1]} << 8 | out[c][2]);
  std::sort(seen.begin(), seen.end());
  r.colours_out = static_cast<uint64_t>(std::unique(seen.begin(), seen.end()) - seen.begin());
  for (size_t i = 0; i < n; ++i) {
    const uint32_t u = slot[i];
    std::copy(out[cluster[u]].begin(), out[cluster[u]].end(), rgb.begin() + 3 * i);
    for (int a = 0; a < 3; ++a) {
      r.mean_rgb[a] += err[u][a];
      r.max_rgb[a] = std::max<double>(r.max_rgb[a], err[u][a]);
    }
    r.mean_delta_e += delta[u];
    r.max_delta_e = std::max(r.max_delta_e, delta[u]);
  }
  for (double& m : r.mean_rgb) m /= double(n);
  r.mean_delta_e /= double(n);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

}  // namespace mv
