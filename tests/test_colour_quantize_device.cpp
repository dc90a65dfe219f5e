// The quantizer's nearest-centre kernel (kernels/common/quantize.h) against the host's k-d tree search, its
// reference (nearest_centres_on_host): the same clusters round by round, and the same palette and colours end to
// end, on every device. Rounds: random colours, colours on a centre and halfway between two (exact ties, which go
// to the lower centre), two equal centres, trees from 2 centres to 4096, starting from the first and the last.
#include <array>
#include <random>

#include "megavox/colour.h"
#include "megavox/colour_quantize.h"
#include "test_support.h"

namespace mv::test {
namespace {

using Lab = std::array<double, 3>;

class ColourQuantizeDeviceTest : public ::testing::TestWithParam<DeviceInfo> {};

Lab random_lab(std::mt19937_64& rng) {
  return {double(rng() % 100), double(rng() % 200) - 100, double(rng() % 200) - 100};
}

TEST_P(ColourQuantizeDeviceTest, RoundsEqualTheHostSearch) {
  Device& dev = shared_device(GetParam());
  const NearestCentres on_device = nearest_centres_on(dev);
  std::mt19937_64 rng(7);
  for (uint32_t k : {2u, 3u, 17u, 256u, 4096u}) {
    SCOPED_TRACE(k);
    std::vector<Lab> centres(k), lab(20000);
    for (Lab& c : centres) c = random_lab(rng);
    centres[k - 1] = centres[0];
    for (size_t i = 0; i < lab.size(); ++i) {
      const Lab& a = centres[rng() % k];
      const Lab& b = centres[rng() % k];
      if (i % 3 == 0) lab[i] = random_lab(rng);
      else if (i % 3 == 1) lab[i] = a;
      else lab[i] = {(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2};
    }
    const std::vector<uint32_t> order = centre_tree_order(centres);
    for (uint32_t start : {0u, k - 1}) {
      std::vector<uint32_t> host(lab.size(), start), device(lab.size(), start);
      const bool host_moved = nearest_centres_on_host(lab, centres, order, host);
      EXPECT_EQ(on_device(lab, centres, order, device), host_moved);
      EXPECT_EQ(device, host);
      // A second round from the answers: nothing moves.
      EXPECT_FALSE(on_device(lab, centres, order, device));
      EXPECT_EQ(device, host);
    }
  }
}

// Whole quantizations: random colours and clumps of near-equal ones, at 4, 8 and 12 bits.
TEST_P(ColourQuantizeDeviceTest, PalettesEqualTheHostQuantizer) {
  Device& dev = shared_device(GetParam());
  std::mt19937_64 rng(11);
  for (uint32_t clumps : {0u, 300u}) {
    std::vector<uint8_t> in;
    for (int i = 0; i < 40000; ++i) {
      uint32_t c = static_cast<uint32_t>(rng() & 0xffffff);
      const uint32_t clump = clumps ? static_cast<uint32_t>(rng() % clumps) : 0;
      if (clumps) c = (clump * 0x0a1b2c3u + static_cast<uint32_t>(rng() % 7)) & 0xffffff;
      in.insert(in.end(), {uint8_t(c >> 16), uint8_t(c >> 8), uint8_t(c)});
    }
    for (uint32_t bits : {4u, 8u, 12u}) {
      SCOPED_TRACE(std::to_string(clumps) + " clumps, " + std::to_string(bits) + " bits");
      std::vector<uint8_t> host = in, device = in;
      const ColourQuantizeReport h = quantize_colours(host, bits);
      const ColourQuantizeReport d = quantize_colours(dev, device, bits);
      EXPECT_EQ(device, host);
      EXPECT_EQ(d.iterations, h.iterations);
      EXPECT_EQ(d.colours_out, h.colours_out);
      EXPECT_EQ(d.max_delta_e, h.max_delta_e);
    }
  }
}

MV_INSTANTIATE_ON_ALL_DEVICES(ColourQuantizeDeviceTest);

}  // namespace
}  // namespace mv::test
