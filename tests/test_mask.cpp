// Masks: the post-processing kernels against their references on every device; GrabCut from a box on
// synthetic images with a known answer, strokes forcing their pixels, the device min-cut equal to Boost's BK
// on GrabCut's graphs of a real photograph (so masks are the same bytes on every device), GrabCut and the
// histogram classifier against the GrabCut database's ground truth, and how starts combine and fail.
#include <cmath>
#include <random>

#include "io/image_reader.h"
#include "io/mvm_file.h"
#include "mask/grabcut.h"
#include "mask/mask_score.h"
#include "mask_reference.h"
#include "min_cut_reference.h"
#include "megavox/mask.h"
#include "megavox/min_cut.h"
#include "test_support.h"

namespace mv::test {
namespace {

// An ellipse of noisy red on a noisy two-tone green background; `truth` 255 inside the ellipse.
RasterImage ellipse_image(uint32_t w, uint32_t h, std::vector<uint16_t>& truth, uint64_t seed) {
  RasterImage img{w, h, 3, 255, std::vector<uint16_t>(size_t{w} * h * 3)};
  truth.assign(size_t{w} * h, 0);
  std::mt19937_64 rng(seed);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t{y} * w + x;
      const double dx = (x - 0.5 * w) / (0.3 * w), dy = (y - 0.5 * h) / (0.35 * h);
      const bool in = dx * dx + dy * dy < 1;
      truth[i] = in ? 255 : 0;
      const int base[3] = {in ? 200 : 40, in ? 50 : ((x / 8 + y / 8) % 2 ? 150 : 110), in ? 40 : 60};
      for (int c = 0; c < 3; ++c)
        img.samples[i * 3 + c] = uint16_t(std::clamp<int64_t>(base[c] + int64_t(rng() % 41) - 20, 0, 255));
    }
  return img;
}

// A sub-image (rows and columns [x, x + w) x [y, y + h)).
RasterImage crop(const RasterImage& img, uint32_t x, uint32_t y, uint32_t w, uint32_t h) {
  RasterImage out{w, h, img.channels, img.max_value, {}};
  for (uint32_t r = y; r < y + h; ++r)
    out.samples.insert(out.samples.end(), img.samples.begin() + (size_t{r} * img.width + x) * img.channels,
                       img.samples.begin() + (size_t{r} * img.width + x + w) * img.channels);
  return out;
}

std::vector<uint16_t> crop_truth(const std::vector<uint16_t>& t, uint32_t tw, uint32_t x, uint32_t y, uint32_t w, uint32_t h) {
  std::vector<uint16_t> out;
  for (uint32_t r = y; r < y + h; ++r) out.insert(out.end(), t.begin() + size_t{r} * tw + x, t.begin() + size_t{r} * tw + x + w);
  return out;
}

// GrabCut with Boost's cut on `dev` (the first device where a test is not per device: every device gives the
// same labels, test_grabcut.cpp).
mask::GrabCutResult grabcut_bk(Device& dev, const RasterImage& img, const std::vector<uint8_t>& labels,
                               uint32_t iterations = 5) {
  mask::GrabCutOptions o;
  o.iterations = iterations;
  return mask::grabcut(dev, img, labels, o, [](const GridGraph& g) { return ref::bk_min_cut(g); });
}

#define MV_MASK_FIRST_DEVICE(dev)                                   \
  if (all_devices().empty()) GTEST_SKIP() << "no device";           \
  Device& dev = shared_device(all_devices().front())

class MaskTest : public ::testing::TestWithParam<DeviceInfo> {
 protected:
  Device& dev() { return shared_device(GetParam()); }
};

TEST_P(MaskTest, PostProcessingMatchesReference) {
  std::mt19937_64 rng(5);
  struct Size {
    uint32_t w, h;
  };
  for (Size s : {Size{1, 1}, Size{3, 2}, Size{37, 29}, Size{64, 50}}) {
    // blobs: random discs, so the median and the erosion both have edges to work on
    std::vector<uint8_t> m(size_t{s.w} * s.h, 0);
    for (int k = 0; k < 6; ++k) {
      const double cx = double(rng() % s.w), cy = double(rng() % s.h), r = 1.0 + double(rng() % 12);
      for (uint32_t y = 0; y < s.h; ++y)
        for (uint32_t x = 0; x < s.w; ++x)
          if ((x - cx) * (x - cx) + (y - cy) * (y - cy) < r * r) m[size_t{y} * s.w + x] = 1;
    }
    for (size_t i = 0; i < m.size(); ++i)
      if (rng() % 10 == 0) m[i] ^= 1;  // salt and pepper for the median
    for (uint32_t r : {0u, 1u, 2u, 4u}) {
      SCOPED_TRACE(std::to_string(s.w) + " x " + std::to_string(s.h) + ", radius " + std::to_string(r));
      std::vector<uint8_t> want = ref::median5(m, s.w, s.h);
      if (r > 0) want = ref::erode_octagon(want, s.w, s.h, r);
      EXPECT_EQ(postprocess_mask(dev(), m, s.w, s.h, r), want);
    }
  }
  EXPECT_NE(error_message([&] { postprocess_mask(dev(), std::vector<uint8_t>(4, 1), 2, 2, 33); }).find("radius 33"),
            std::string::npos);
}

TEST_P(MaskTest, BoxStartFindsTheEllipse) {
  std::vector<uint16_t> truth;
  const RasterImage img = ellipse_image(96, 72, truth, 3);
  MaskStart start;
  start.box = mask::box_from_truth(truth, img.width, img.height);
  const MaskResult r = mask_image(dev(), img, start, {5, false, 0});
  EXPECT_LT(mask::mask_error(r.grabcut, truth), 0.01);
  EXPECT_EQ(r.mask, r.grabcut);  // --no-post
  EXPECT_GE(r.iterations, 1u);
  EXPECT_NEAR(r.foreground, 0.33, 0.03);  // pi * 0.3 * 0.35
  const MaskResult post = mask_image(dev(), img, start, {5, true, 2});
  EXPECT_LT(mask::mask_error(post.mask, truth), 0.05);
  EXPECT_LT(post.foreground, r.foreground);  // erosion takes the rim
}

TEST_P(MaskTest, StrokesForceTheirPixels) {
  std::vector<uint16_t> truth;
  const RasterImage img = ellipse_image(80, 60, truth, 4);
  MaskStart start;
  start.box = mask::box_from_truth(truth, img.width, img.height);
  start.seeds.assign(size_t{img.width} * img.height, 128);
  for (uint32_t x = 30; x < 50; ++x) start.seeds[30 * size_t{img.width} + x] = 0;  // through the ellipse
  for (uint32_t y = 2; y < 12; ++y) start.seeds[y * size_t{img.width} + 3] = 255;  // in the background
  const MaskResult r = mask_image(dev(), img, start, {5, false, 0});
  for (uint32_t x = 30; x < 50; ++x) EXPECT_EQ(r.grabcut[30 * size_t{img.width} + x], 0) << x;
  for (uint32_t y = 2; y < 12; ++y) EXPECT_EQ(r.grabcut[y * size_t{img.width} + 3], 255) << y;
}

// Every cut of GrabCut on a crop of a real photograph: the device's value and source set are Boost's.
TEST_P(MaskTest, RealPhotographGraphsMatchBoykovKolmogorov) {
  MV_SKIP_WITHOUT_SHARED_DATA("grabcut/images/llama.ppm");
  const RasterImage full = io::read_image(shared_data_file("grabcut/images/llama.ppm"));
  const RasterImage truth_img = io::read_image(shared_data_file("grabcut/masks/llama.pgm"));
  const uint32_t w = std::min(full.width, 200u), h = std::min(full.height, 150u);
  const uint32_t x0 = (full.width - w) / 2, y0 = (full.height - h) / 2;
  const RasterImage img = crop(full, x0, y0, w, h);
  const std::vector<uint16_t> truth = crop_truth(truth_img.samples, full.width, x0, y0, w, h);
  mask::GrabCutOptions o;
  o.iterations = 3;
  uint32_t cuts = 0;
  const auto labels = start_labels(img, MaskStart{mask::box_from_truth(truth, w, h), {}, nullptr});
  MinCutFlow flow;  // as mask_image cuts: each iteration from the last one's flow
  const mask::GrabCutResult r = mask::grabcut(dev(), img, labels, o, [&](const GridGraph& g) {
    MinCutStats st;
    const MinCut want = ref::bk_min_cut(g), got = min_cut(dev(), g, {}, &st, &flow);
    EXPECT_EQ(got.value, want.value) << "cut " << cuts;
    EXPECT_TRUE(got.source_side == want.source_side) << "cut " << cuts;
    EXPECT_EQ(st.warm, cuts > 0) << "cut " << cuts;
    ++cuts;
    return got;
  });
  EXPECT_EQ(r.labels, grabcut_bk(dev(), img, labels, 3).labels);
  EXPECT_GE(cuts, 1u);
}

MV_INSTANTIATE_ON_ALL_DEVICES(MaskTest);

// GrabCut (host, with Boost's cut: the device's is the same, above) and the classifier on six images.
TEST(MaskGroundTruth, GrabCutAndClassifierOnSixImages) {
  MV_SKIP_WITHOUT_SHARED_DATA("grabcut/images/llama.ppm");
  MV_MASK_FIRST_DEVICE(dev);
  const char* names[] = {"llama", "teddy", "106024", "153093", "189080", "376043"};
  double grabcut_sum = 0;
  std::vector<RasterImage> images;
  std::vector<std::vector<uint16_t>> truths;
  for (const char* name : names) {
    images.push_back(io::read_image(shared_data_file(std::string("grabcut/images/") + name + ".ppm")));
    truths.push_back(io::read_image(shared_data_file(std::string("grabcut/masks/") + name + ".pgm")).samples);
    const RasterImage& img = images.back();
    const MaskBox box = mask::box_from_truth(truths.back(), img.width, img.height);
    const auto r = grabcut_bk(dev, img, mask::box_labels(img.width, img.height, box.x, box.y, box.w, box.h));
    const double err = mask::mask_error(mask::labels_to_mask(r.labels), truths.back());
    std::printf("  %-8s grabcut error %.2f %% (%u iterations)\n", name, 100 * err, r.iterations);
    grabcut_sum += err;
  }
  EXPECT_LT(grabcut_sum / 6, 0.08);
  // The classifier trained on each image alone, thresholded on that image at 0.5.
  double classifier_sum = 0;
  for (size_t k = 0; k < images.size(); ++k) {
    MaskModel m = MaskModel::empty(3);
    m.train(images[k], truths[k], images[k].width, images[k].height);
    std::vector<uint8_t> mask(truths[k].size());
    for (size_t i = 0; i < mask.size(); ++i) mask[i] = m.probability(images[k], i) > 0.5 ? 255 : 0;
    classifier_sum += mask::mask_error(mask, truths[k]);
  }
  std::printf("  classifier on its own image: mean error %.2f %%\n", 100 * classifier_sum / 6);
  EXPECT_LT(classifier_sum / 6, 0.25);
}

// A graph too large for scale 256: the first iteration's scale is kept, so every iteration's edges are the first
// one's and each cut can start from the last one's flow (MinCutFlow needs the same edges).
TEST(MaskQuantization, LaterIterationsKeepTheFirstScale) {
  MV_MASK_FIRST_DEVICE(dev);
  std::vector<uint16_t> truth;
  const RasterImage img = ellipse_image(800, 600, truth, 5);
  const MaskBox box = mask::box_from_truth(truth, img.width, img.height);
  std::vector<uint32_t> first_edges;
  uint32_t cuts = 0;
  mask::GrabCutOptions o;
  const std::vector<uint8_t> start = mask::box_labels(img.width, img.height, box.x, box.y, box.w, box.h);
  const mask::GrabCutResult r = mask::grabcut(dev, img, start, o, [&](const GridGraph& g) {
    if (cuts == 0) first_edges = g.edges;
    EXPECT_TRUE(g.edges == first_edges) << "cut " << cuts;
    MinCut c;  // a cut that moves every time (the truth less every fifth column, another each cut): all five run
    c.source_side.resize(truth.size());
    for (size_t i = 0; i < truth.size(); ++i) c.source_side[i] = truth[i] != 0 && (i % img.width) % 5 != cuts;
    ++cuts;
    return c;
  });
  EXPECT_EQ(cuts, 5u);
  EXPECT_LT(r.scale, 256.0);  // the case that needs the rule
}

TEST(MaskStarts, CombineAndFail) {
  MV_MASK_FIRST_DEVICE(dev);
  std::vector<uint16_t> truth;
  const RasterImage img = ellipse_image(20, 10, truth, 1);
  EXPECT_NE(error_message([&] { start_labels(img, {}); }).find("no start"), std::string::npos);
  MaskStart s;
  s.box = MaskBox{2, 2, 10, 5};
  s.seeds.assign(200, 128);
  s.seeds[0] = 255;   // outside the box: the seed wins
  s.seeds[45] = 64;   // inside
  std::vector<uint8_t> l = start_labels(img, s);
  EXPECT_EQ(l[0], mask::kForeground);
  EXPECT_EQ(l[45], mask::kProbableBackground);
  EXPECT_EQ(l[44], mask::kProbableForeground);  // 128: the box's word
  EXPECT_EQ(l[199], mask::kBackground);
  s.box.reset();
  EXPECT_EQ(start_labels(img, s)[44], mask::kUnknown);
  MaskModel grey = MaskModel::empty(1);
  grey.fg[3] = 1;
  s.model = &grey;
  EXPECT_NE(error_message([&] { start_labels(img, s); }).find("1-channel images, the image has 3 channels"),
            std::string::npos);
  s.model = nullptr;
  s.seeds.pop_back();
  EXPECT_NE(error_message([&] { start_labels(img, s); }).find("size"), std::string::npos);
  s.seeds.clear();
  s.box = MaskBox{15, 0, 10, 5};
  EXPECT_NE(error_message([&] { start_labels(img, s); }).find("does not lie inside"), std::string::npos);
  // Only foreground strokes: nothing to learn the background from.
  s.box.reset();
  s.seeds.assign(200, 255);
  EXPECT_NE(error_message([&] { grabcut_bk(dev, img, start_labels(img, s)); }).find("no background"), std::string::npos);
}

TEST(MaskModelFile, RoundTripAndDamage) {
  std::vector<uint16_t> truth;
  const RasterImage img = ellipse_image(40, 30, truth, 2);
  MaskModel m = MaskModel::empty(3);
  m.train(img, truth, 40, 30);
  const std::string path = temp_path("m.mvm");
  io::write_mvm(path, m);
  const MaskModel back = io::read_mvm(path);
  EXPECT_EQ(back.channels, 3u);
  EXPECT_EQ(back.fg, m.fg);
  EXPECT_EQ(back.bg, m.bg);
  std::vector<char> c = file_bytes(path);
  std::vector<uint8_t> b(c.begin(), c.end());
  auto why = [](std::vector<uint8_t> bytes) { return error_message([&] { io::decode_mvm(bytes, "x"); }); };
  EXPECT_EQ(why(b), "");
  auto flip = b;
  flip[100] ^= 1;
  EXPECT_NE(why(flip).find("checksum"), std::string::npos);
  auto cut = b;
  cut.pop_back();
  EXPECT_NE(why(cut).find("truncated"), std::string::npos);
  auto ver = b;
  ver[8] = 2;
  EXPECT_NE(why(ver).find("version 2"), std::string::npos);
  auto ch = b;
  ch[12] = 2;
  EXPECT_NE(why(ch).find("2 channels"), std::string::npos);
  EXPECT_NE(why({'h', 'i'}).find("not a .mvm"), std::string::npos);
  EXPECT_NE(error_message([&] { m.train(img, truth, 30, 40); }).find("the mask is 30 x 40"), std::string::npos);
}

}  // namespace
}  // namespace mv::test
