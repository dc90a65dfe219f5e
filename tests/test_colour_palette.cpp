// Palette compression of the colour array (megavox/colour_palette.h): decode equals encode, entry by entry and
// in bulk, on random arrays of several kinds and on edge cases (one entry, one colour, all distinct, block
// boundaries); the same bytes every run; damaged bytes an error; and through .mvx files of every encoding on
// every device, with the writer keeping the smaller of raw and palette.
#include <cmath>
#include <fstream>
#include <random>

#include "io/mvx_format.h"
#include "megavox/build.h"
#include "megavox/colour_palette.h"
#include "megavox/colour_quantize.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "point_fixture.h"
#include "test_support.h"

namespace mv::test {
namespace {

// n colours: runs of random length from a pool of `pool` colours (pool 0: every colour random).
std::vector<uint8_t> palette_test_colours(size_t n, uint32_t pool, uint32_t max_run, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<uint32_t> colours(std::max<uint32_t>(pool, 1));
  for (uint32_t& c : colours) c = static_cast<uint32_t>(rng() & 0xffffff);
  std::vector<uint8_t> out;
  while (out.size() < 3 * n) {
    const uint32_t c = pool ? colours[rng() % pool] : static_cast<uint32_t>(rng() & 0xffffff);
    for (uint32_t r = 1 + static_cast<uint32_t>(rng() % max_run); r > 0 && out.size() < 3 * n; --r)
      out.insert(out.end(), {uint8_t(c >> 16), uint8_t(c >> 8), uint8_t(c)});
  }
  return out;
}

// Encode, check the structure, decode every entry alone and in bulk, serialise, parse and decode again.
void check_palette_round_trip(const std::vector<uint8_t>& rgb, const std::string& what) {
  SCOPED_TRACE(what);
  const ColourPalette p = palette_encode(rgb);
  const uint64_t n = rgb.size() / 3;
  ASSERT_EQ(p.entries, n);
  ASSERT_GE(p.blocks(), 1u);
  ASSERT_EQ(p.block_start[0], 0u);
  for (size_t g = 1; g < p.blocks(); ++g) ASSERT_GT(p.block_start[g], p.block_start[g - 1]);
  for (uint16_t s : p.palette_size) ASSERT_TRUE(s >= 1 && s <= 256);
  EXPECT_EQ(p.decode(), rgb);
  for (uint64_t i = 0; i < n; ++i) {
    const auto c = p.colour(i);
    ASSERT_TRUE(std::equal(c.begin(), c.end(), rgb.begin() + 3 * i)) << "entry " << i;
  }
  const std::vector<uint8_t> bytes = palette_serialise(p);
  const ColourPalette back = palette_parse(bytes, n, p.blocks(), p.palettes());
  EXPECT_EQ(back.decode(), rgb);
  EXPECT_EQ(palette_serialise(back), bytes);
  EXPECT_EQ(palette_serialise(palette_encode(rgb)), bytes) << "not deterministic";
}

TEST(ColourPalette, RandomArraysDecodeAsEncoded) {
  uint64_t seed = 1;
  for (size_t n : {2u, 7u, 100u, 1000u, 20000u})
    for (uint32_t pool : {0u, 1u, 3u, 17u, 300u, 5000u})
      for (uint32_t run : {1u, 4u, 200u})
        check_palette_round_trip(palette_test_colours(n, pool, run, ++seed),
                                 "n " + std::to_string(n) + ", pool " + std::to_string(pool) + ", run " + std::to_string(run));
}

TEST(ColourPalette, EdgeCases) {
  check_palette_round_trip({10, 20, 30}, "one entry");
  check_palette_round_trip(std::vector<uint8_t>(3 * 5000, 77), "one colour");
  std::vector<uint8_t> distinct;
  for (uint32_t c = 0; c < 70000; ++c) distinct.insert(distinct.end(), {uint8_t(c >> 16), uint8_t(c >> 8), uint8_t(c * 7)});
  check_palette_round_trip(distinct, "all distinct");
  // Long runs of 1, 2, 4, 8, 16 colours one after the other: phase 1's blocks meet phase 2's at every boundary.
  std::vector<uint8_t> staged;
  for (uint32_t k : {1u, 2u, 4u, 8u, 16u, 256u, 257u, 3u})
    for (uint32_t i = 0; i < 700; ++i) staged.insert(staged.end(), {uint8_t(k), uint8_t(i % k), uint8_t(i % k >> 8)});
  const ColourPalette p = palette_encode(staged);
  EXPECT_GT(p.blocks(), 4u);
  for (size_t g = 0; g < p.blocks(); ++g)
    for (uint64_t i : {uint64_t{p.block_start[g]}, uint64_t{p.block_start[g]} + 1, uint64_t{p.block_start[g]} - 1})
      if (i < p.entries) {
        const auto c = p.colour(i);
        ASSERT_TRUE(std::equal(c.begin(), c.end(), staged.begin() + 3 * i)) << "entry " << i;
      }
  check_palette_round_trip(staged, "staged runs");
  // One colour stays one block of zero-bit indices: only the head, one material and the directory.
  const ColourPalette one = palette_encode(std::vector<uint8_t>(3 * 5000, 9));
  EXPECT_EQ(one.blocks(), 1u);
  EXPECT_EQ(one.index_bits(), 0u);
}

// Coherent colours compress; noise does not, and the .mvx writer then keeps raw.
TEST(ColourPalette, CoherentCompressesNoiseDoesNot) {
  const std::vector<uint8_t> coherent = palette_test_colours(50000, 40, 50, 3);
  EXPECT_LT(palette_serialise(palette_encode(coherent)).size(), coherent.size() / 4);
  const std::vector<uint8_t> noise = palette_test_colours(50000, 0, 1, 4);
  EXPECT_GT(palette_serialise(palette_encode(noise)).size(), noise.size());
}

// The thesis's Table 2.1 accounting (notes A.9), which megavox's figures follow: the raw attribute array A is 3 bytes
// an entry (MB = 2^20 bytes, M = 10^6), the fixed-width alternative Ã + M is ⌈log2 λ⌉ bits an entry plus 24 bits a
// material, and the compression rate is PC / A. Then megavox's own palette of coherent colours: its material
// indices are ⌈log2 λ⌉ bits wide, and it is smaller than that fixed-width alternative, as PC is in every scene.
TEST(ColourPalette, ThesisAccountingIdentities) {
  struct Scene {
    double entries_m, materials_m, a_mb, fixed_mb, pc_mb, rate;
  } scenes[] = {{4760, 1.66, 13619, 11922, 10124, 0.74},
                {10487, 1.42, 30004, 26257, 24051, 0.80},
                {14788, 3.15, 42309, 38792, 10877, 0.26},
                {3263, 1.57, 9336, 8174, 2220, 0.24}};
  for (const Scene& s : scenes) {
    const double entries = s.entries_m * 1e6, materials = s.materials_m * 1e6, mb = 1024.0 * 1024.0;
    // the table's Λ and λ have 3 to 5 digits: its sizes agree to about 1 MB
    EXPECT_NEAR(entries * 3 / mb, s.a_mb, 1.5);
    EXPECT_NEAR((entries * std::ceil(std::log2(materials)) + 24 * materials) / 8 / mb, s.fixed_mb, 1.5);
    EXPECT_NEAR(s.pc_mb / s.a_mb, s.rate, 0.005);
  }
  const std::vector<uint8_t> rgb = palette_test_colours(60000, 300, 40, 11);
  const ColourPalette p = palette_encode(rgb);
  const double materials = double(p.materials_count()), entries = double(p.entries);
  EXPECT_EQ(p.material_bits, uint32_t(std::ceil(std::log2(materials))));
  const double fixed_bytes = (entries * p.material_bits + 24 * materials) / 8;
  EXPECT_LT(double(palette_serialise(p).size()), fixed_bytes);
  EXPECT_LT(double(palette_serialise(p).size()), 3 * entries);
}

// Every single damaged byte, and every truncation, is an mv::Error or a palette that still decodes in range.
TEST(ColourPalette, DamagedBytesAreErrors) {
  const std::vector<uint8_t> rgb = palette_test_colours(300, 9, 7, 5);
  const ColourPalette p = palette_encode(rgb);
  const std::vector<uint8_t> good = palette_serialise(p);
  for (size_t at = 0; at < good.size(); ++at)
    for (uint8_t flip : {uint8_t{1}, uint8_t{0x80}, uint8_t{0xff}}) {
      std::vector<uint8_t> bad = good;
      bad[at] ^= flip;
      try {
        const ColourPalette q = palette_parse(bad, p.entries, p.blocks(), p.palettes());
        EXPECT_EQ(q.decode().size(), rgb.size());
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("colour palette"), std::string::npos);
      }
    }
  for (size_t size = 0; size < good.size(); size += 8)
    EXPECT_THROW(palette_parse(std::span(good).first(size), p.entries, p.blocks(), p.palettes()), Error);
  EXPECT_THROW(palette_parse(good, p.entries, p.blocks() + 1, p.palettes()), Error);
  EXPECT_THROW(palette_parse(good, p.entries, p.blocks(), p.palettes() + 1), Error);
  EXPECT_THROW(palette_parse(good, uint64_t{1} << 40, p.blocks(), p.palettes()), Error);
}

TEST(ColourQuantize, LabAndDeltaE94) {
  const uint8_t white[3] = {255, 255, 255}, black[3] = {0, 0, 0}, red[3] = {255, 0, 0};
  const auto w = srgb_to_lab(white), k = srgb_to_lab(black), r = srgb_to_lab(red);
  EXPECT_NEAR(w[0], 100, 1e-3);
  EXPECT_NEAR(w[1], 0, 1e-2);
  EXPECT_NEAR(w[2], 0, 1e-2);
  EXPECT_NEAR(k[0], 0, 1e-9);
  EXPECT_NEAR(r[0], 53.24, 0.01);
  EXPECT_NEAR(r[1], 80.09, 0.01);
  EXPECT_NEAR(r[2], 67.20, 0.01);
  EXPECT_DOUBLE_EQ(delta_e94({50, 10, 10}, {50, 10, 10}), 0);
  EXPECT_NEAR(delta_e94({50, 0, 0}, {60, 0, 0}), 10, 1e-12);
  EXPECT_NEAR(delta_e94({50, 30, 0}, {50, 20, 0}), 10 / 2.35, 1e-12);          // chroma: S_C = 1 + 0.045 C1
  EXPECT_NEAR(delta_e94({50, 30, 0}, {50, 0, 30}), std::sqrt(1800) / 1.45, 1e-12);  // hue: S_H = 1 + 0.015 C1
  std::vector<uint8_t> rgb = {1, 2, 3};
  EXPECT_THROW(quantize_colours(rgb, 0), Error);
  EXPECT_THROW(quantize_colours(rgb, 25), Error);
}

// At most 2^bits colours out, the same bytes every run, the reported errors those of the output, and few
// colours (or 24 bits) unchanged.
TEST(ColourQuantize, BoundedDeterministicAndReported) {
  for (uint32_t bits : {4u, 8u, 12u}) {
    SCOPED_TRACE(bits);
    const std::vector<uint8_t> in = palette_test_colours(30000, 0, 3, 20 + bits);
    std::vector<uint8_t> a = in, b = in;
    const ColourQuantizeReport r = quantize_colours(a, bits);
    quantize_colours(b, bits);
    EXPECT_EQ(a, b);
    std::vector<uint32_t> seen;
    double mean[3] = {}, max[3] = {}, de = 0, de_max = 0;
    for (size_t i = 0; i < in.size() / 3; ++i) {
      seen.push_back(uint32_t{a[3 * i]} << 16 | uint32_t{a[3 * i + 1]} << 8 | a[3 * i + 2]);
      for (int c = 0; c < 3; ++c) {
        const double e = std::abs(int(a[3 * i + c]) - int(in[3 * i + c]));
        mean[c] += e;
        max[c] = std::max(max[c], e);
      }
      const double d = delta_e94(srgb_to_lab(&in[3 * i]), srgb_to_lab(&a[3 * i]));
      de += d;
      de_max = std::max(de_max, d);
    }
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
    EXPECT_LE(seen.size(), size_t{1} << bits);
    EXPECT_EQ(seen.size(), r.colours_out);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(r.mean_rgb[c], mean[c] / double(in.size() / 3), 1e-9);
      EXPECT_EQ(r.max_rgb[c], max[c]);
    }
    EXPECT_NEAR(r.mean_delta_e, de / double(in.size() / 3), 1e-9);
    EXPECT_NEAR(r.max_delta_e, de_max, 1e-12);
    EXPECT_GT(r.mean_delta_e, 0);
  }
  const std::vector<uint8_t> few = palette_test_colours(5000, 100, 4, 9);
  std::vector<uint8_t> q = few;
  EXPECT_EQ(quantize_colours(q, 12).colours_out, quantize_colours(q, 12).colours_in);
  EXPECT_EQ(q, few);
  q = palette_test_colours(5000, 0, 1, 9);
  const std::vector<uint8_t> kept = q;
  EXPECT_EQ(quantize_colours(q, 24).max_delta_e, 0);
  EXPECT_EQ(q, kept);
}

class ColourPaletteFilesTest : public ::testing::TestWithParam<DeviceInfo> {};

// A clumped cloud of `colours` colours on a 32^3 grid, as a PLY file.
std::string palette_cloud_ply(uint32_t colours, uint64_t seed, const std::string& name) {
  std::mt19937_64 rng(seed);
  std::vector<points::PlyColumn> cols = {{"float", "x", {}}, {"float", "y", {}}, {"float", "z", {}},
                                         {"uchar", "red", {}}, {"uchar", "green", {}}, {"uchar", "blue", {}}};
  double centre[3] = {};
  uint32_t rgb = 0;
  for (int p = 0; p < 4000; ++p) {
    if (p % 100 == 0) {
      for (double& a : centre) a = double(rng() % 24);
      rgb = colours ? static_cast<uint32_t>(rng() % colours) * 0x10305 : 0;
    }
    for (int a = 0; a < 3; ++a) cols[a].values.push_back(centre[a] + double(rng() % 800) / 100.0);
    const uint32_t c = colours ? rgb : static_cast<uint32_t>(rng() & 0xffffff);
    for (int k = 0; k < 3; ++k) cols[3 + k].values.push_back(c >> (8 * k) & 255);
  }
  const std::string path = temp_path(name);
  std::ofstream(path, std::ios::binary) << points::make_cloud_ply(ply::Fmt::le, cols);
  return path;
}

// Every encoding: the build keeps the smaller storage; palette and raw files of the same colours read back the
// same; the palette counts reach `megavox info` through read_mvx; bits never pass raw's.
TEST_P(ColourPaletteFilesTest, EveryEncodingRoundTrips) {
  Device& dev = shared_device(GetParam());
  for (uint32_t colours : {0u, 1u, 6u}) {
    const std::string in = palette_cloud_ply(colours, 11 + colours, "palette_" + std::to_string(colours) + ".ply");
    for (Encoding e : {Encoding::svdag, Encoding::ssvdag, Encoding::ussvdag, Encoding::svo}) {
      SCOPED_TRACE(encoding_name(e) + ", colours " + std::to_string(colours));
      const BuildOptions o = points::cloud_build_options(in, temp_path("palette_" + encoding_name(e) + ".mvx"), 32, e);
      const BuildReport r = build_mvx(dev, o);
      {  // quantized to 3 bits: at most 8 colours, recorded in the file and checked when read
        BuildOptions q = o;
        q.output = temp_path("palette_q_" + encoding_name(e) + ".mvx");
        q.colour_bits = 3;
        const BuildReport rq = build_mvx(dev, q);
        EXPECT_EQ(rq.colour_quantize.bits, 3u);
        EXPECT_LE(rq.colour_quantize.colours_out, 8u);
        const MvxFile fq = read_mvx(q.output);
        EXPECT_EQ(fq.colour_bits, 3u);
        EXPECT_EQ(decode_encoded(fq.dag), decode_encoded(read_mvx(o.output).dag));
      }
      const uint64_t raw = 32 + 3 * r.colour_entries;
      EXPECT_EQ(r.colour_bytes, std::min(raw, r.colour_palette_bytes));
      EXPECT_EQ(r.colour_format, colours ? "palette" : "raw");
      MvxFile f = read_mvx(o.output);
      EXPECT_EQ(encoded_octree_nodes(f.dag), f.svo_nodes);
      EXPECT_EQ(f.colour_stats.bytes, r.colour_bytes);
      EXPECT_EQ(f.colour_stats.format, colours ? 1u : 0u);
      if (colours) {
        EXPECT_GE(f.colour_stats.blocks, 1u);
      }
      for (ColourStorage s : {ColourStorage::raw, ColourStorage::palette}) {
        f.colour_storage = s;
        const std::string again = temp_path("palette_again.mvx");
        const MvxColourStats w = write_mvx(again, f);
        const MvxFile back = read_mvx(again);
        EXPECT_EQ(back.colours, f.colours);
        EXPECT_EQ(back.colour_stats.bytes, w.bytes);
        EXPECT_EQ(back.colour_stats.blocks, w.blocks);
        EXPECT_EQ(back.colour_stats.palettes, w.palettes);
        EXPECT_EQ(back.colour_stats.format, s == ColourStorage::palette ? 1u : 0u);
      }
    }
  }
}

MV_INSTANTIATE_ON_ALL_DEVICES(ColourPaletteFilesTest);

}  // namespace
}  // namespace mv::test
