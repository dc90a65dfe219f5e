// Paged addresses past 2^32 stream words: a built ssvdag's top levels (a built svdag's bottom ones) moved 2^32
// words up a sparse virtual stream (the pages between are never read), traced through a small cache on every
// device, from memory and from a sparse .mvx whose page index says so (through the C API too). Its page ids pass
// 2^20 at 16 KiB pages, the walk's child addresses cross 2^32 words, and the hits equal the resident DAG's.
#include <fcntl.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <random>

#include "megavox/build.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "megavox/trace.h"
#include "paging/paged_ssvdag.h"
#include "trace/trace_engine.h"
#include "cache/page_cache.h"
#include "io/mvx_format.h"
#include "io/mvx_pages.h"
#include "megavox/megavox.h"
#include "test_support.h"

namespace mv::test {
namespace {

class PagedWideTest : public ::testing::TestWithParam<DeviceInfo> {};

constexpr uint32_t kWidePageWords = 4096;              // 16 KiB pages
constexpr uint64_t kWideGap = uint64_t{1} << 33;        // 16-bit words: 2^32 stream words, whole pages

// A closed mesh of a few thousand random triangles around the unit sphere, built as an ssvdag at 2^levels.
MvxFile wide_sample(Device& dev, uint32_t levels, Encoding encoding = Encoding::ssvdag) {
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
  o.encoding = encoding;
  build_mvx(dev, o);
  return read_mvx(out);
}

namespace fmt = mvx_format;

// Where 16-bit word h of the moved stream comes from in the original one (levels from `moved` on went up by
// kWideGap; `end` is the original's length): its index, or ~0 for the gap.
uint64_t wide_source(uint64_t h, uint64_t moved, uint64_t end) {
  if (h < moved) return h;
  if (h >= moved + kWideGap && h < end + kWideGap) return h - kWideGap;
  return ~uint64_t{0};
}

// Page vp (P words) of the moved stream, from the original stream's words.
std::vector<uint32_t> wide_page(const std::vector<uint32_t>& words, uint64_t vp, uint32_t P, uint64_t moved,
                                uint64_t end) {
  std::vector<uint32_t> out(P, 0);
  for (uint32_t i = 0; i < P; ++i)
    for (uint32_t k = 0; k < 2; ++k) {
      const uint64_t from = wide_source(2 * (vp * P + i) + k, moved, end);
      if (from != ~uint64_t{0}) out[i] |= ((words[from >> 1] >> (16 * (from & 1))) & 0xffffu) << (16 * k);
    }
  return out;
}

// Rays from around the unit cube toward random points near its centre.
std::vector<Ray> wide_rays(size_t n, uint64_t seed) {
  std::vector<Ray> rays(n);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (Ray& r : rays)
    for (int a = 0; a < 3; ++a) {
      r.origin[a] = 3.0f * u(rng);
      r.direction[a] = 0.8f * u(rng) - r.origin[a];
    }
  return rays;
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
  d.read = [=](uint32_t page, std::span<uint32_t> out) {
    const std::vector<uint32_t> w = wide_page(*words, page, kWidePageWords, moved, end);
    std::copy(w.begin(), w.end(), out.begin());
  };
  ASSERT_GT(d.pages, 1u << 20);
  ASSERT_GT(starts[L] / 2, uint64_t{1} << 32);  // the root's word

  const std::vector<Ray> rays = wide_rays(300, 3);
  Tracer resident(dev, f);
  const std::vector<RayHit> want = resident.trace(rays);
  Tracer wide(dev, d, 256 * uint64_t{kWidePageWords} * 4);  // 256 slots of the 2^20 and more pages
  EXPECT_THROW(wide.engine().set_level_starts(TraceEngine::LevelStarts::parameters), Error);  // past 32 bits
  EXPECT_GT(expect_same_hits(wide.trace(rays), want), rays.size() / 4);
}

// `small` (a paged .mvx from write_mvx in level order) with levels moved kWideGap 16-bit words (2^32 words) up
// the stream, written as `out`: an ssvdag's top two levels, a word stream's bottom two (its root stays at word
// 0). The nodes section (last, sparse: only the pages that hold nodes are written) passes 2^32 words, the page
// index lists every page, the paged starts say where the levels went; every checksum right.
void write_wide_mvx(const std::string& small, const std::string& out) {
  const std::vector<char> b = file_bytes(small);
  fmt::Header h;
  std::memcpy(&h, b.data(), sizeof h);
  auto find = [&](uint32_t kind) -> const fmt::Section& {
    for (uint32_t i = 0; i < h.sections; ++i)
      if (h.table[i].kind == kind) return h.table[i];
    throw Error("no section " + std::to_string(kind));
  };
  fmt::PageIndexHead head;
  std::memcpy(&head, b.data() + find(fmt::kPageIndex).offset, sizeof head);
  const uint32_t P = head.page_words, L = h.levels;
  std::vector<uint32_t> words(head.words);
  std::memcpy(words.data(), b.data() + find(fmt::kNodes).offset, words.size() * 4);
  std::vector<uint64_t> starts(find(fmt::kPagedStarts).bytes / 8);
  std::memcpy(starts.data(), b.data() + find(fmt::kPagedStarts).offset, starts.size() * 8);
  const bool compact = h.encoding == static_cast<uint32_t>(Encoding::ssvdag);  // starts in 16-bit words
  const uint64_t moved = compact ? starts[L - 1] : 2 * starts[2], end = 2 * head.words;
  for (uint32_t l = compact ? L - 1 : 1; l <= (compact ? L : 2); ++l) starts[l] += compact ? kWideGap : kWideGap / 2;
  const uint64_t W = (end + kWideGap + 1) / 2, pages = (W + P - 1) / P;
  auto page = [&](uint64_t vp) { return wide_page(words, vp, P, moved, end); };
  const uint64_t low = (moved / 2 + P - 1) / P, high = (moved + kWideGap) / 2 / P;  // pages [low, high): the gap
  std::vector<uint64_t> index(3 + pages);
  const fmt::PageIndexHead wide{P, head.order, pages, W};
  std::memcpy(index.data(), &wide, sizeof wide);
  const std::vector<uint32_t> zeros(P, 0);
  const uint64_t zero_hash = fmt::page_hash(zeros.data(), P, P);
  for (uint64_t vp = 0; vp < pages; ++vp)
    index[3 + vp] = vp >= low && vp < high ? zero_hash : fmt::page_hash(page(vp).data(), std::min<uint64_t>(P, W - vp * P), P);
  // the sections as they were, but the index and the starts new and the nodes last
  fmt::Header w = h;
  w.sections = 0;
  std::vector<std::pair<const void*, uint64_t>> data;
  uint64_t offset = fmt::kPage;
  auto add = [&](uint32_t kind, const void* d, uint64_t bytes, bool checked) {
    w.table[w.sections++] = {kind, 0, offset, bytes, checked ? fmt::hash(d, bytes) : 0};
    data.push_back({d, bytes});
    offset += (bytes + fmt::kPage - 1) / fmt::kPage * fmt::kPage;
  };
  for (uint32_t i = 0; i < h.sections; ++i) {
    const fmt::Section& s = h.table[i];
    if (s.kind == fmt::kPageIndex) add(s.kind, index.data(), index.size() * 8, true);
    else if (s.kind == fmt::kPagedStarts) add(s.kind, starts.data(), starts.size() * 8, true);
    else if (s.kind != fmt::kNodes) add(s.kind, b.data() + s.offset, s.bytes, true);
  }
  const uint64_t nodes_at = offset;
  w.table[w.sections++] = {fmt::kNodes, 0, nodes_at, W * 4, 0};
  w.checksum = fmt::hash(&w, offsetof(fmt::Header, checksum));
  const int fd = ::open(out.c_str(), O_CREAT | O_TRUNC | O_WRONLY, 0644);
  ASSERT_GE(fd, 0);
  std::vector<char> first(fmt::kPage, 0);
  std::memcpy(first.data(), &w, sizeof w);
  ASSERT_EQ(::pwrite(fd, first.data(), first.size(), 0), ssize_t(first.size()));
  for (uint32_t i = 0; i + 1 < w.sections; ++i)
    ASSERT_EQ(::pwrite(fd, data[i].first, data[i].second, off_t(w.table[i].offset)), ssize_t(data[i].second));
  for (uint64_t vp = 0; vp < pages; ++vp) {
    if (vp >= low && vp < high) continue;  // a hole: reads as zeros
    const std::vector<uint32_t> words_of = page(vp);
    const uint64_t n = std::min<uint64_t>(P, W - vp * P) * 4;
    ASSERT_EQ(::pwrite(fd, words_of.data(), n, off_t(nodes_at + vp * P * 4)), ssize_t(n));
  }
  ASSERT_EQ(::ftruncate(fd, off_t(nodes_at + (W * 4 + fmt::kPage - 1) / fmt::kPage * fmt::kPage)), 0);
  ::close(fd);
}

void sparse_file_opens_and_traces(const DeviceInfo& on, Encoding encoding) {
  Device& dev = shared_device(on);
  const MvxFile f = wide_sample(dev, 8, encoding);
  const std::string small = temp_path("wide_small.mvx"), out = temp_path("wide_sparse.mvx");
  write_mvx(small, f, MvxPaging{kWidePageWords, NodeOrder::level});
  write_wide_mvx(small, out);
  {
    const MvxPages pages(out);
    EXPECT_GT(pages.pages(), 1u << 20);
    EXPECT_GT(pages.words(), uint64_t{1} << 32);
  }
  const std::vector<Ray> rays = wide_rays(200, 8);
  Tracer resident(dev, f);
  const std::vector<RayHit> want = resident.trace(rays);
  Tracer wide(dev, open_paged_mvx(out), 256 * uint64_t{kWidePageWords} * 4);
  expect_same_hits(wide.trace(rays), want);
  // the C API opens it paged, streams it through a 64 MiB budget and answers the resident scene's bytes
  const std::string config = "device=" + on.selector() + ",memory=64M";
  MvDevice d = mvNewDevice(config.c_str());
  ASSERT_TRUE(d);
  MvScene scene = mvOpenScene(d, out.c_str()), flat = mvOpenScene(d, small.c_str());
  ASSERT_TRUE(scene && flat) << mvGetDeviceLastErrorMessage(d);
  MvSceneInfo info;
  ASSERT_EQ(mvGetSceneInfo(scene, &info), MV_ERROR_NONE);
  EXPECT_GT(info.bytes, uint64_t{16} << 30);
  std::vector<MvTraceRay> crays(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    std::memcpy(crays[i].org, rays[i].origin, 12);
    std::memcpy(crays[i].dir, rays[i].direction, 12);
    crays[i].tmax = INFINITY;
  }
  std::vector<MvTraceHit> a(rays.size()), c(rays.size());
  ASSERT_EQ(mvTraceRays(flat, crays.data(), a.data(), a.size(), nullptr), MV_ERROR_NONE);
  ASSERT_EQ(mvTraceRays(scene, crays.data(), c.data(), c.size(), nullptr), MV_ERROR_NONE) << mvGetDeviceLastErrorMessage(d);
  EXPECT_EQ(std::memcmp(a.data(), c.data(), a.size() * sizeof(MvTraceHit)), 0);
  MvSceneStats st{};
  st.byteSize = sizeof st;
  ASSERT_EQ(mvGetSceneStats(scene, &st), MV_ERROR_NONE);
  EXPECT_EQ(st.paged, 1u);
  EXPECT_LE(st.peakDeviceBytes, uint64_t{64} << 20);
  mvReleaseScene(scene);
  mvReleaseScene(flat);
  mvReleaseDevice(d);
  std::filesystem::remove(out);
}

// An ssvdag, and a word stream in level order, whose pointers count from their level's start: those of level 3
// reach level 2 past 2^32 words. One test, the files one after the other: lavapipe under ASan holds ~13 GB for
// each (its allocations are not lazy there), and two side by side would pass a 24 GB machine.
TEST_P(PagedWideTest, ASparseFilePast2To32WordsOpensAndTraces) {
  for (Encoding e : {Encoding::ssvdag, Encoding::svdag}) {
    SCOPED_TRACE(encoding_name(e));
    sparse_file_opens_and_traces(GetParam(), e);
  }
}

MV_INSTANTIATE_ON_ALL_DEVICES(PagedWideTest);

}  // namespace
}  // namespace mv::test
