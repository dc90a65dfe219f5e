// GrabCut's kernels (kernels/common/grabcut*.h) against their plain references (host/ref/grabcut_reference.h) on
// every device, random and edge inputs, bit for bit; the exp and log they use against the C library's; and
// whole GrabCut runs giving the same labels on every device.
#include <cmath>
#include <random>

#include "grabcut_reference.h"
#include "io/image_reader.h"
#include "mask/grabcut.h"
#include "mask/grabcut_kernels.h"
#include "mask/mask_score.h"
#include "min_cut_reference.h"
#include "test_support.h"

namespace mv::test {
namespace {

using mask::GrabCutConsts;
using mask::GrabCutKernels;

// Random samples (some runs of equal colour, so distances of 0 occur), `channels` per pixel up to max_value.
RasterImage gc_random_image(uint32_t w, uint32_t h, uint32_t channels, uint32_t max_value, uint64_t seed) {
  RasterImage img{w, h, channels, max_value, std::vector<uint16_t>(size_t{w} * h * channels)};
  std::mt19937_64 rng(seed);
  for (size_t i = 0; i < img.samples.size(); ++i)
    img.samples[i] = rng() % 4 == 0 && i >= channels ? img.samples[i - channels] : uint16_t(rng() % (max_value + 1));
  return img;
}

std::vector<uint8_t> gc_random_labels(size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<uint8_t> l(n);
  for (auto& v : l) v = uint8_t(rng() % 5);
  return l;
}

// A mixture fitted from random moments of random colours; component `absent` gets no pixel, component 4 a single
// colour (a singular covariance).
std::array<mask::Gaussian, 5> gc_random_mixture(uint64_t seed, int absent) {
  std::mt19937_64 rng(seed);
  mask::Moments m{};
  for (int k = 0; k < 5; ++k) {
    if (k == absent) continue;
    const uint32_t base[3] = {uint32_t(rng() % 256), uint32_t(rng() % 256), uint32_t(rng() % 256)};
    const int count = k == 4 ? 3 : 20 + int(rng() % 50);
    for (int s = 0; s < count; ++s) {
      uint64_t z[3];
      for (int a = 0; a < 3; ++a) z[a] = k == 4 ? base[a] : std::min<uint64_t>(255, base[a] + rng() % (10 + 30 * a));
      m[k][0] += 1;
      for (int a = 0; a < 3; ++a) m[k][1 + a] += z[a];
      m[k][4] += z[0] * z[0], m[k][5] += z[0] * z[1], m[k][6] += z[0] * z[2];
      m[k][7] += z[1] * z[1], m[k][8] += z[1] * z[2], m[k][9] += z[2] * z[2];
    }
  }
  return mask::fit_mixture(m);
}

ref::GcMixture gc_ref_mixture(const std::array<mask::Gaussian, 5>& g) {
  ref::GcMixture r;
  for (int k = 0; k < 5; ++k) {
    r[k].present = g[k].weight > 0;
    std::copy(g[k].mean, g[k].mean + 3, r[k].mean);
    std::copy(g[k].inverse, g[k].inverse + 9, r[k].inverse);
    r[k].energy = g[k].energy;
  }
  return r;
}

struct GcSize {
  uint32_t w, h, channels, max_value;
};
// The last is large enough that a summing work-item takes hundreds of pixels on a CPU device, whose loops a
// loop-capped device (lavapipe) would cut short if the launch did not account for them.
const GcSize kGcSizes[] = {{1, 1, 3, 255},     {3, 2, 1, 255},       {37, 29, 3, 255},
                           {64, 50, 3, 1023},  {130, 70, 1, 65535},  {481, 321, 3, 255}};

TEST(GrabCutMath, ExpAndLogAreWithinAFewUlps) {
  std::mt19937_64 rng(1);
  for (int i = 0; i < 20000; ++i) {
    const double x = i < 10000 ? double(rng() % 1000000) * 1e-4 : double(rng() % 7000000) * 1e-4;
    const double want = std::exp(-x);
    EXPECT_NEAR(ref::gc_exp_neg(x), want, want * 1e-15) << x;
    const double t = 1 + double(rng() % 4000000) * 1e-6;
    EXPECT_NEAR(ref::gc_log(t), std::log(t), 1e-15 * std::log(t) + 1e-300) << t;
  }
  EXPECT_EQ(ref::gc_exp_neg(0), 1.0);
  EXPECT_EQ(ref::gc_exp_neg(707), 0.0);
  EXPECT_EQ(ref::gc_log(1), 0.0);
}

class GrabCutKernelTest : public ::testing::TestWithParam<DeviceInfo> {
 protected:
  Device& dev() { return shared_device(GetParam()); }
};

TEST_P(GrabCutKernelTest, ColoursSmoothnessAndEdgesMatchReference) {
  uint64_t seed = 10;
  for (const GcSize& s : kGcSizes) {
    SCOPED_TRACE(std::to_string(s.w) + " x " + std::to_string(s.h) + " x " + std::to_string(s.channels));
    const RasterImage img = gc_random_image(s.w, s.h, s.channels, s.max_value, ++seed);
    GrabCutKernels gk(dev(), img, gc_random_labels(size_t{s.w} * s.h, seed));
    const std::vector<uint32_t> colour = ref::gc_colours(img);
    EXPECT_EQ(gk.colours(), colour);
    EXPECT_EQ(gk.beta_sum(), ref::gc_beta_sum(colour, s.w, s.h));
    for (double beta : {0.0, 1.0 / 7000, 0.37, 1e3}) {
      GrabCutConsts c;
      c.v[MV_GC_BETA] = beta, c.v[MV_GC_GAMMA] = 50, c.v[MV_GC_GAMMA_DIAG] = 50 / std::sqrt(2.0);
      c.v[MV_GC_SCALE] = 3.7 + beta;
      gk.upload_consts(c);
      EXPECT_EQ(gk.smooth_sum(), ref::gc_smooth_sum(colour, s.w, s.h, beta, 50)) << beta;
      std::vector<uint32_t> edges;
      gk.edges(edges);
      EXPECT_EQ(edges, ref::gc_edges(colour, s.w, s.h, beta, 50, 3.7 + beta)) << beta;
    }
  }
}

TEST_P(GrabCutKernelTest, DataTermsAndComponentsMatchReference) {
  uint64_t seed = 20;
  for (const GcSize& s : kGcSizes) {
    SCOPED_TRACE(std::to_string(s.w) + " x " + std::to_string(s.h));
    const size_t n = size_t{s.w} * s.h;
    const RasterImage img = gc_random_image(s.w, s.h, s.channels, s.max_value, ++seed);
    const std::vector<uint8_t> labels = gc_random_labels(n, seed);
    GrabCutKernels gk(dev(), img, labels);
    const std::vector<uint32_t> colour = ref::gc_colours(img);
    std::vector<uint32_t> comp(n);
    std::mt19937_64 rng(seed);
    for (auto& v : comp) v = uint32_t(rng() % 5) | uint32_t(rng() % 5) << 8;
    const auto bg = gc_random_mixture(seed, 1), fg = gc_random_mixture(seed + 100, s.w % 2 ? 5 : 0);
    GrabCutConsts c;
    c.set_mixture(0, bg), c.set_mixture(1, fg);
    c.v[MV_GC_LAMBDA] = 450, c.v[MV_GC_SCALE] = 11.25;
    gk.upload_consts(c);
    for (bool own : {true, false}) {
      gk.set_components(comp);
      const ref::GcData want = ref::gc_data(colour, labels, comp, gc_ref_mixture(bg), gc_ref_mixture(fg), 450, own);
      EXPECT_EQ(gk.data(own), own ? 0 : want.sum) << own;
      EXPECT_EQ(gk.components(), want.comp) << own;
      if (own) continue;
      EXPECT_EQ(gk.terms(), want.terms);
      std::vector<uint32_t> src, snk, want_src, want_snk;
      gk.terminals(src, snk);
      ref::gc_terminals(want.terms, 11.25, want_src, want_snk);
      EXPECT_EQ(src, want_src);
      EXPECT_EQ(snk, want_snk);
    }
  }
}

TEST_P(GrabCutKernelTest, MomentsKmeansSeedingAndLabelsMatchReference) {
  uint64_t seed = 30;
  for (const GcSize& s : kGcSizes) {
    SCOPED_TRACE(std::to_string(s.w) + " x " + std::to_string(s.h));
    const size_t n = size_t{s.w} * s.h;
    const RasterImage img = gc_random_image(s.w, s.h, s.channels, s.max_value, ++seed);
    std::vector<uint8_t> labels = gc_random_labels(n, seed);
    GrabCutKernels gk(dev(), img, labels);
    const std::vector<uint32_t> colour = ref::gc_colours(img);
    std::mt19937_64 rng(seed);
    std::vector<uint32_t> comp(n);
    for (auto& v : comp) v = uint32_t(rng() % 5) | uint32_t(rng() % 5) << 8;
    gk.set_components(comp);
    const auto m = gk.moments();
    const std::vector<uint64_t> want_m = ref::gc_moments(colour, labels, comp);
    for (int side = 0; side < 2; ++side)
      for (int k = 0; k < 5; ++k)
        for (int c = 0; c < 10; ++c) EXPECT_EQ(m[side][k][c], want_m[(side * 5 + k) * 10 + c]);
    // k-means: random centres, 1 to 5 a side, some equal (ties go to the lower index)
    double centres[2][5][3];
    const uint32_t count[2] = {uint32_t(1 + rng() % 5), 5};
    GrabCutConsts c;
    for (int side = 0; side < 2; ++side)
      for (int k = 0; k < 5; ++k) {
        for (int a = 0; a < 3; ++a) centres[side][k][a] = k == 3 ? centres[side][1][a] : double(rng() % 2560) / 10;
        c.set_centre(side, k, centres[side][k]);
      }
    gk.upload_consts(c);
    const auto sums = gk.kmeans(count);
    const std::vector<uint64_t> want_sums = ref::gc_kmeans(colour, labels, comp, centres, count);
    EXPECT_EQ(gk.components(), comp);
    for (int side = 0; side < 2; ++side)
      for (int k = 0; k < 5; ++k)
        for (int a = 0; a < 4; ++a) EXPECT_EQ(sums[side][k][a], want_sums[(side * 5 + k) * 4 + a]);
    // seeding: ranks, then distances to a centre, then the least with a second one; draws over the whole range
    std::vector<uint32_t> d2[2];
    uint32_t centre[2] = {0x102030, 0x00ff80};
    for (uint32_t mode : {0u, 1u, 2u}) {
      if (mode == 2) centre[0] = 0x808080, centre[1] = 0x010203;
      const std::array<uint64_t, 2> total = gk.seed_d2(mode, 3, centre);
      for (int side = 0; side < 2; ++side) {
        d2[side] = ref::gc_seed_d2(colour, labels, side, mode, d2[side], centre[side]);
        uint64_t t = 0;
        for (uint32_t v : d2[side]) t += v;
        EXPECT_EQ(total[side], t) << mode;
      }
      for (int draw = 0; draw < 4 && total[0] > 0 && total[1] > 0; ++draw) {
        const uint64_t pick[2] = {draw == 0 ? 0 : draw == 3 ? total[0] - 1 : rng() % total[0],
                                  draw == 0 ? 0 : draw == 3 ? total[1] - 1 : rng() % total[1]};
        uint32_t found_colour[2];
        const std::array<uint32_t, 2> found = gk.seed_find(3, pick, found_colour);
        for (int side = 0; side < 2; ++side) {
          EXPECT_EQ(found[side], ref::gc_seed_find(d2[side], pick[side])) << mode << " " << draw;
          EXPECT_EQ(found_colour[side], colour[found[side]]);
        }
      }
    }
    // a cut: labels follow it except the hard ones
    std::vector<uint8_t> side_of(n);
    for (auto& v : side_of) v = uint8_t(rng() % 2);
    const uint64_t changed = gk.update_labels(side_of);
    EXPECT_EQ(changed, ref::gc_labels(labels, side_of));
    EXPECT_EQ(gk.labels(), labels);
    EXPECT_EQ(gk.update_labels(side_of), 0u);
  }
}

MV_INSTANTIATE_ON_ALL_DEVICES(GrabCutKernelTest);

// Whole runs: the same labels on every device (the cut is Boost's BK, so only the kernels can differ), on a
// synthetic image and a whole photograph (where a summing work-item takes hundreds of pixels).
TEST(GrabCutDevices, EveryDeviceGivesTheSameLabels) {
  std::vector<std::pair<RasterImage, std::vector<uint8_t>>> cases;
  {
    RasterImage img = gc_random_image(90, 70, 3, 255, 7);
    for (uint32_t y = 20; y < 50; ++y)  // a reddish block inside the box
      for (uint32_t x = 25; x < 65; ++x) img.samples[(size_t{y} * 90 + x) * 3] = 230, img.samples[(size_t{y} * 90 + x) * 3 + 1] /= 4;
    cases.push_back({img, mask::box_labels(90, 70, 15, 10, 60, 50)});
  }
  if (!shared_data_file("grabcut/images/106024.ppm").empty()) {  // a whole photograph, with its database box
    const RasterImage img = io::read_image(shared_data_file("grabcut/images/106024.ppm"));
    const RasterImage truth = io::read_image(shared_data_file("grabcut/masks/106024.pgm"));
    const MaskBox box = mask::box_from_truth(truth.samples, img.width, img.height);
    cases.push_back({img, mask::box_labels(img.width, img.height, box.x, box.y, box.w, box.h)});
  }
  for (size_t c = 0; c < cases.size(); ++c) {
    std::vector<uint8_t> first;
    for (const DeviceInfo& d : all_devices()) {
      SCOPED_TRACE("case " + std::to_string(c) + " on " + d.selector());
      const mask::GrabCutResult r = mask::grabcut(shared_device(d), cases[c].first, cases[c].second, {},
                                                  [](const GridGraph& g) { return ref::bk_min_cut(g); });
      EXPECT_GE(r.iterations, 1u);
      if (first.empty()) first = r.labels;
      EXPECT_EQ(r.labels, first);
    }
  }
}

}  // namespace
}  // namespace mv::test
