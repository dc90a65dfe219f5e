// Paged addresses past 2^32 stream words: a built ssvdag's top levels moved 2^32 words up a sparse virtual
// stream (the pages between are never read), traced through a small cache on every device. Its page ids pass
// 2^20 at 16 KiB pages, the walk's child addresses cross 2^32 words, and the hits equal the resident DAG's.
#include <random>

#include "megavox/build.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "megavox/trace.h"
#include "paging/paged_ssvdag.h"
#include "trace/trace_engine.h"
#include "cache/page_cache.h"
#include "test_support.h"

namespace mv::test {
namespace {

class PagedWideTest : public ::testing::TestWithParam<DeviceInfo> {};

constexpr uint32_t kWidePageWords = 4096;              // 16 KiB pages
constexpr uint64_t kWideGap = uint64_t{1} << 33;        // 16-bit words: 2^32 stream words, whole pages

// A closed mesh of a few thousand random triangles around the unit sphere, built as an ssvdag at 2^levels.
MvxFile wide_sample(Device& dev, uint32_t levels) {
  std::mt19937_64 rng(5);
  std::normal_distribution<float> n(0, 1);
  std::vector<float> pos;
  std::vector<uint32_t> idx;
  for (uint32_t t = 0; t < 3000; ++t) {
    float c[3] = {n(rng), n(rng), n(rng)};
    const float len = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) + 1e-6f;
    for (int v = 0; v < 3; ++v) {
      for (int a = 0; a < 3; ++a) pos.push_back(c[a] / len + 0.08f * n(rng));
      idx.push_back(3 * t + v);
    }
  }
  const std::string ply = temp_path("wide.ply"), out = temp_path("wide.mvx");
  write_ply(ply, pos, idx);
  BuildOptions o;
  o.input = ply;
  o.output = out;
  o.resolution = 1u << levels;
  o.encoding = Encoding::ssvdag;
  build_mvx(dev, o);
  return read_mvx(out);
}

TEST_P(PagedWideTest, AnSsvdagPast2To32WordsResolves) {
  Device& dev = shared_device(GetParam());
  const MvxFile f = wide_sample(dev, 8);
  const uint32_t L = f.dag.levels;
  const PagedSsvdag s = paged_ssvdag(f.dag, kWidePageWords);
  // the top two levels move up by kWideGap 16-bit words; everything below stays
  const uint64_t moved = s.starts[L - 1], end = 2 * uint64_t{s.words.size()};
  std::vector<uint64_t> starts = s.starts;
  for (uint32_t l = L - 1; l <= L; ++l) starts[l] += kWideGap;
  PagedDag d;
  d.grid = f.grid;
  d.bounds = f.bounds;
  d.encoding = Encoding::ssvdag;
  d.levels = L;
  d.page_words = kWidePageWords;
  d.pages = static_cast<uint32_t>((end + kWideGap + 2 * kWidePageWords - 1) / (2 * kWidePageWords));
  d.level_starts = starts;
  const std::vector<uint32_t>* words = &s.words;
  auto half = [words](uint64_t h) { return ((*words)[h >> 1] >> (16 * (h & 1))) & 0xffffu; };
  d.read = [=](uint32_t page, std::span<uint32_t> out) {
    for (uint32_t i = 0; i < out.size(); ++i) {
      uint32_t w = 0;
      for (uint32_t k = 0; k < 2; ++k) {
        const uint64_t h = 2 * (uint64_t{page} * out.size() + i) + k;  // this 16-bit word, virtual
        const uint64_t from = h < moved ? h : h >= moved + kWideGap && h < end + kWideGap ? h - kWideGap : ~uint64_t{0};
        if (from != ~uint64_t{0}) w |= half(from) << (16 * k);
      }
      out[i] = w;
    }
  };
  ASSERT_GT(d.pages, 1u << 20);
  ASSERT_GT(starts[L] / 2, uint64_t{1} << 32);  // the root's word

  std::vector<Ray> rays(300);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (Ray& r : rays)
    for (int a = 0; a < 3; ++a) {
      r.origin[a] = 3.0f * u(rng);
      r.direction[a] = 0.8f * u(rng) - r.origin[a];
    }
  Tracer resident(dev, f);
  const std::vector<RayHit> want = resident.trace(rays);
  Tracer wide(dev, d, 256 * uint64_t{kWidePageWords} * 4);  // 256 slots of the 2^20 and more pages
  EXPECT_THROW(wide.engine().set_level_starts(TraceEngine::LevelStarts::parameters), Error);  // past 32 bits
  const std::vector<RayHit> got = wide.trace(rays);
  size_t hits = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    SCOPED_TRACE("ray " + std::to_string(i));
    ASSERT_EQ(got[i].hit, want[i].hit);
    ASSERT_FALSE(got[i].coarse);
    hits += got[i].hit;
    EXPECT_EQ(got[i].t, want[i].t);
    EXPECT_EQ(got[i].level, want[i].level);
    EXPECT_EQ(got[i].steps, want[i].steps);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(got[i].cell[a], want[i].cell[a]);
  }
  EXPECT_GT(hits, rays.size() / 4);
}

MV_INSTANTIATE_ON_ALL_DEVICES(PagedWideTest);

}  // namespace
}  // namespace mv::test
