// The paged ssvdag (host/formats/paging/paged_ssvdag.h) on host-built DAGs: the round trip through pages gives the
// resident encoding back byte for byte at every page size, no node crosses a page, pointers that grow past 13
// bits with the padding take 32 bits, paging costs little space at realistic page sizes, and a damaged paged
// stream is a clear error, never a read out of bounds.
#include <algorithm>
#include <random>

#include "paging/paged_ssvdag.h"
#include "test_support.h"

namespace mv::test {
namespace {

// Every voxel set of a 2^levels grid as an ssvdag (a plain DAG: every tag 0), and a dense random one whose
// level 3 is long enough for 32-bit pointers.
std::vector<std::pair<std::string, EncodedDag>> ssvdag_cases(uint32_t levels) {
  std::vector<std::pair<std::string, EncodedDag>> out;
  for (auto& [name, voxels] : voxel_sets(levels)) out.emplace_back(name, encode_ssvdag(host_dag(voxels, levels, true)));
  std::mt19937_64 rng(7);
  std::vector<uint64_t> dense;
  for (int i = 0; i < 60000; ++i) dense.push_back(rng() % (uint64_t{1} << (3 * levels)));
  out.emplace_back("dense", encode_ssvdag(host_dag(sorted_unique(dense), levels, true)));
  return out;
}

// Mirror tags on every pointer of the stream (a valid ssvdag of other voxels: tags only reflect children).
EncodedDag with_mirror_tags(EncodedDag enc, uint64_t seed) {
  std::mt19937_64 rng(seed);
  for (uint64_t w = 0; w < enc.inner.size();) {
    const uint32_t header = enc.inner[w++];
    for (int t = 7; t >= 0; --t) {
      const uint32_t code = header >> (2 * t) & 3;
      if (code == 0) continue;
      enc.inner[w] = static_cast<uint16_t>((enc.inner[w] & 0x1fffu) | (rng() % 8) << 13);
      w += code == 1 ? 1 : 2;
    }
  }
  return enc;
}

bool same_ssvdag(const EncodedDag& a, const EncodedDag& b) {
  return a.inner == b.inner && a.bricks == b.bricks && a.level_offset == b.level_offset && a.levels == b.levels;
}

uint32_t paged_header_at(const PagedSsvdag& p, uint64_t w16) {
  return reinterpret_cast<const uint16_t*>(p.words.data())[w16];
}

TEST(PagedSsvdag, RoundTripIsByteForByte) {
  for (const auto& [name, enc0] : ssvdag_cases(7)) {
    for (const EncodedDag& enc : {enc0, with_mirror_tags(enc0, enc0.inner.size())}) {
      for (uint32_t pw : {10u, 16u, 100u, 4096u}) {
        SCOPED_TRACE(name + " " + std::to_string(pw));
        const PagedSsvdag p = paged_ssvdag(enc, pw);
        ASSERT_EQ(p.starts.size(), enc.levels + 1u);
        EXPECT_EQ(p.starts[1], enc.bricks.size());
        EXPECT_EQ(paged_header_at(p, p.starts[enc.levels]), enc.inner[0]) << "the root leads the last level";
        const EncodedDag back = ssvdag_from_pages(p.words, p.starts, enc.levels, pw);
        EXPECT_TRUE(same_ssvdag(back, enc));
      }
    }
  }
}

TEST(PagedSsvdag, NodesStayInTheirPagesAndLongOffsetsTake32Bits) {
  const EncodedDag enc = ssvdag_cases(7).back().second;  // dense
  // Level 3 is longer than 2^13 16-bit words: some resident pointers are 32-bit already.
  ASSERT_GT(enc.level_offset[3] == 0 ? 0 : enc.inner.size() - enc.level_offset[3], 1u << 13);
  const uint32_t pw = 10;  // 20 16-bit words: a node of up to 17 leaves little room, so padding is frequent
  const PagedSsvdag p = paged_ssvdag(enc, pw);
  const auto* in = reinterpret_cast<const uint16_t*>(p.words.data());
  uint64_t nodes = 0, padding = 0;
  for (uint32_t l = 3; l <= enc.levels; ++l) {
    const uint64_t end = l == enc.levels ? p.words.size() * 2 : p.starts[l + 1];
    for (uint64_t w = p.starts[l]; w < end;) {
      if (in[w] == 0) {
        ++padding, ++w;
        continue;
      }
      uint64_t size = 1;
      for (uint32_t t = 0; t < 8; ++t) size += std::min<uint32_t>(in[w] >> (2 * t) & 3, 2);
      EXPECT_EQ(w / (2 * pw), (w + size - 1) / (2 * pw)) << "node at 16-bit word " << w;
      ++nodes;
      w += size;
    }
  }
  EXPECT_GT(padding, 0u);
  EXPECT_GT(nodes, 1000u);
  EXPECT_TRUE(same_ssvdag(ssvdag_from_pages(p.words, p.starts, enc.levels, pw), enc));
}

TEST(PagedSsvdag, SizeWithinFivePercentAtRealisticPages) {
  int measured = 0;
  for (const auto& [name, enc] : ssvdag_cases(8)) {
    if (enc.bytes() < 64 * 1024) continue;  // a page or two: the last page is not padded, the rest is noise
    ++measured;
    for (uint32_t pw : {1024u, 4096u}) {
      const PagedSsvdag p = paged_ssvdag(enc, pw);
      EXPECT_LE(p.words.size() * 4.0, enc.bytes() * 1.05 + 4) << name << " " << pw;
    }
  }
  EXPECT_GE(measured, 1);
}

TEST(PagedSsvdag, EmptyAndUnpageable) {
  EncodedDag empty;
  empty.encoding = Encoding::ssvdag;
  empty.levels = 5;
  empty.level_offset.assign(6, 0);
  EXPECT_TRUE(paged_ssvdag(empty, 4096).words.empty());
  EXPECT_TRUE(ssvdag_from_pages({}, {}, 5, 4096).inner.empty());
  const EncodedDag enc = ssvdag_cases(5)[0].second;
  EXPECT_NE(error_message([&] { paged_ssvdag(enc, 8); }).find("cannot hold a node"), std::string::npos);
  EXPECT_NE(error_message([&] {
              paged_ssvdag(encode_svdag(host_dag(voxel_sets(5)[0].second, 5, true)), 64);
            }).find("not an ssvdag"),
            std::string::npos);
}

TEST(PagedSsvdag, DamageIsAClearError) {
  const EncodedDag enc = with_mirror_tags(ssvdag_cases(7).back().second, 1);
  const uint32_t pw = 64;
  const PagedSsvdag good = paged_ssvdag(enc, pw);
  const uint32_t L = enc.levels;
  auto expect_error = [&](const std::vector<uint32_t>& words, const std::vector<uint64_t>& starts,
                          const std::string& what, uint32_t page = 64) {
    const std::string why = error_message([&] { ssvdag_from_pages(words, starts, L, page); });
    EXPECT_NE(why.find(what), std::string::npos) << "'" << why << "' lacks '" << what << "'";
  };
  std::vector<uint64_t> starts = good.starts;
  starts[4] = starts[5] + 1;
  expect_error(good.words, starts, "out of order");
  starts = good.starts;
  starts[1] += 1;
  expect_error(good.words, starts, "bricks do not end");
  starts = good.starts;
  starts.pop_back();
  expect_error(good.words, starts, "level starts");
  // Read with smaller pages than it was made with: some node crosses a boundary, or padding is misplaced.
  EXPECT_THROW(ssvdag_from_pages(good.words, good.starts, L, 10), Error);
  // The root's header cleared: its level holds no node.
  std::vector<uint32_t> words = good.words;
  auto* w16 = reinterpret_cast<uint16_t*>(words.data());
  w16[good.starts[L]] = 0;
  EXPECT_THROW(ssvdag_from_pages(words, good.starts, L, pw), Error);
  // A word after the root.
  words = good.words;
  words.push_back(5);
  expect_error(words, good.starts, "follows the root");
  // Cut short.
  words.assign(good.words.begin(), good.words.begin() + good.words.size() / 2);
  EXPECT_THROW(ssvdag_from_pages(words, good.starts, L, pw), Error);
  // Random damage: an error or a valid ssvdag, nothing in between (and no read out of bounds under ASan).
  std::mt19937_64 rng(3);
  for (int i = 0; i < 2000; ++i) {
    words = good.words;
    starts = good.starts;
    for (int f = 0; f < 1 + i % 3; ++f) {
      uint32_t& w = words[rng() % words.size()];
      w ^= 1u << (rng() % 32);
    }
    if (i % 50 == 0) starts[3 + rng() % (L - 2)] += rng() % 64;
    try {
      const EncodedDag back = ssvdag_from_pages(words, starts, L, pw);
      EXPECT_NO_THROW(validate_ssvdag(back));
    } catch (const Error&) {
    }
  }
}

}  // namespace
}  // namespace mv::test
