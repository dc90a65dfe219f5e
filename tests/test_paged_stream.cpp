// The paged node stream (host/formats/paging/paged_stream.h) on host-built octrees and DAGs of every 32-bit encoding:
// the round trip through a page layout and back to level order keeps the voxels, the word count and the level
// offsets (and the bytes of a stream already in discovery order), paging costs little space at realistic page
// sizes, and a damaged paged stream is a clear error, never a read out of bounds.
#include <algorithm>
#include <random>

#include "paging/paged_stream.h"
#include "test_support.h"

namespace mv::test {
namespace {

struct Case {
  std::string name;
  EncodedDag enc;
};

// The svdag stream of a DAG with random mirror bits on its pointers: a valid ussvdag of other voxels.
EncodedDag with_mirror_bits(EncodedDag enc, uint64_t seed) {
  std::mt19937_64 rng(seed);
  enc.encoding = Encoding::ussvdag;
  for (uint32_t l = enc.levels; l >= 2; --l) {
    for (uint64_t w = enc.level_offset[l]; w < enc.level_offset[l - 1];) {
      const uint32_t mask = enc.words[w] & 0xffu;
      enc.words[w] |= (static_cast<uint32_t>(rng()) & (mask * 0x10101u)) << 8;
      w += 1 + __builtin_popcount(mask);
    }
  }
  return enc;
}

// Every 32-bit encoding of every voxel set of a 2^levels grid, and the full grid.
std::vector<Case> cases(uint32_t levels) {
  std::vector<Case> out;
  auto sets = voxel_sets(levels);
  std::vector<uint64_t> full(uint64_t{1} << 3 * 4);
  for (uint64_t k = 0; k < full.size(); ++k) full[k] = k;
  for (auto& [name, voxels] : sets) {
    out.push_back({name + " svo", encode_svdag(host_dag(voxels, levels, false))});
    out.push_back({name + " svdag", encode_svdag(host_dag(voxels, levels, true))});
    out.push_back({name + " ussvdag", with_mirror_bits(out.back().enc, voxels.size())});
  }
  out.push_back({"full svo", encode_svdag(host_dag(full, 4, false))});
  out.push_back({"full svdag", encode_svdag(host_dag(full, 4, true))});
  return out;
}

EncodedDag round_trip(const EncodedDag& enc, NodeOrder order, uint32_t page_words) {
  const PageLayout lay = page_layout(enc, order, page_words);
  const EncodedDag paged = paged_stream(enc, lay);
  EXPECT_EQ(paged.words.size(), lay.words);
  EXPECT_EQ(paged.level_offset.empty(), order == NodeOrder::subtree);  // level order: relative pointers
  EXPECT_EQ(paged.encoding, enc.encoding);
  return level_order_stream(paged, page_words);
}

TEST(PagedStream, RoundTripKeepsVoxelsSizeAndLevels) {
  for (const Case& c : cases(6)) {
    const std::vector<uint64_t> voxels = decode_svdag(c.enc);
    for (NodeOrder o : {NodeOrder::level, NodeOrder::subtree}) {
      for (uint32_t pw : {9u, 16u, 100u, 4096u}) {
        SCOPED_TRACE(c.name + " " + node_order_name(o) + " " + std::to_string(pw));
        const EncodedDag back = round_trip(c.enc, o, pw);
        ASSERT_NO_THROW(validate_svdag(back));
        EXPECT_EQ(back.encoding, c.enc.encoding);
        EXPECT_EQ(back.words.size(), c.enc.words.size());
        EXPECT_EQ(back.level_offset, c.enc.level_offset);
        EXPECT_TRUE(decode_svdag(back) == voxels);
        // In discovery order already: paging again gives the same bytes.
        EXPECT_TRUE(round_trip(back, NodeOrder::subtree, 16).words == back.words);
        EXPECT_TRUE(round_trip(back, o, pw).words == back.words);
      }
    }
  }
}

TEST(PagedStream, OctreesComeBackByteForByte) {
  // An octree's levels are in Morton order, which is the order the way back discovers them.
  for (const Case& c : cases(6)) {
    if (c.name.find("svo") == std::string::npos) continue;
    SCOPED_TRACE(c.name);
    EXPECT_TRUE(round_trip(c.enc, NodeOrder::subtree, 64).words == c.enc.words);
  }
}

TEST(PagedStream, PageOfExactlyOneLargestNode) {
  // The full grid's octree: every inner node has 8 children (9 words), so each fills a 9-word page.
  std::vector<uint64_t> full(uint64_t{1} << 3 * 3);
  for (uint64_t k = 0; k < full.size(); ++k) full[k] = k;
  const EncodedDag enc = encode_svdag(host_dag(full, 3, false));
  for (NodeOrder o : {NodeOrder::level, NodeOrder::subtree}) {
    const PageLayout lay = page_layout(enc, o, 9);
    const EncodedDag paged = paged_stream(enc, lay);
    EXPECT_EQ(paged.words.size(), enc.words.size());  // 9-word nodes and 1-word leaves: no padding
    for (uint32_t q = 1; q <= 8; ++q) EXPECT_EQ(paged.words[q] % 9, 0u);  // each child of the root starts a page
    const EncodedDag back = level_order_stream(paged, 9);
    EXPECT_TRUE(decode_svdag(back) == full);
    EXPECT_EQ(back.words.size(), enc.words.size());
  }
}

TEST(PagedStream, SizeWithinFivePercentAtRealisticPages) {
  for (auto& [name, voxels] : voxel_sets(8)) {
    for (bool reduce : {false, true}) {
      const EncodedDag enc = encode_svdag(host_dag(voxels, 8, reduce));
      for (NodeOrder o : {NodeOrder::level, NodeOrder::subtree}) {
        for (uint32_t pw : {1024u, 4096u}) {
          const EncodedDag paged = paged_stream(enc, page_layout(enc, o, pw));
          EXPECT_LE(paged.words.size(), enc.words.size() * 1.05 + 8)
              << name << (reduce ? " svdag " : " svo ") << node_order_name(o) << " " << pw;
        }
      }
    }
  }
}

TEST(PagedStream, EmptyAndUnpageable) {
  EncodedDag empty;
  empty.levels = 5;
  empty.level_offset.assign(6, 0);
  const EncodedDag back = level_order_stream(paged_stream(empty, page_layout(empty, NodeOrder::subtree, 16)), 16);
  EXPECT_TRUE(back.words.empty());
  EXPECT_EQ(back.level_offset, empty.level_offset);
  EncodedDag compact;
  compact.encoding = Encoding::ssvdag;
  EXPECT_NE(error_message([&] { level_order_stream(compact, 4096); }).find("ssvdag"), std::string::npos);
  EXPECT_NE(error_message([&] { level_order_stream(empty, 8); }).find("cannot hold a node"), std::string::npos);
  // A layout made for another DAG.
  const auto sets = voxel_sets(5);
  const EncodedDag a = encode_svdag(host_dag(sets[0].second, 5, true));
  const EncodedDag b = encode_svdag(host_dag(sets[1].second, 5, true));
  EXPECT_NE(error_message([&] { paged_stream(a, page_layout(b, NodeOrder::subtree, 64)); }).find("does not fit"),
            std::string::npos);
}

TEST(PagedStream, DamageIsAClearError) {
  const EncodedDag enc = encode_svdag(host_dag(voxel_sets(6)[0].second, 6, true));
  const PageLayout lay = page_layout(enc, NodeOrder::subtree, 64);
  const EncodedDag good = paged_stream(enc, lay);
  ASSERT_GT(good.words.size(), 4 * 64u);
  auto expect_error = [&](const EncodedDag& bad, const std::string& words, uint32_t pw = 64) {
    const std::string why = error_message([&] { level_order_stream(bad, pw); });
    EXPECT_NE(why.find(words), std::string::npos) << "'" << why << "' lacks '" << words << "'";
  };
  // The root's last pointer (its first child in Morton order) is at word popcount(mask).
  const uint32_t root_ptr = __builtin_popcount(good.words[0] & 0xffu);
  EncodedDag bad = good;
  bad.words[root_ptr] = static_cast<uint32_t>(good.words.size()) + 5;
  expect_error(bad, "past the end");
  bad = good;
  bad.words[root_ptr] = 1;  // inside the root
  expect_error(bad, "not the start of a node");
  bad = good;
  bad.words[root_ptr] = 0;  // back to the root: a cycle, the root reached at two levels
  expect_error(bad, "not the start of a node of level");
  bad = good;
  bad.words[good.words[root_ptr]] = 0;  // the child's header
  expect_error(bad, "not a node header");
  bad = good;
  bad.words[good.words[root_ptr]] |= 1u << 9;  // a mirror bit in an svdag
  expect_error(bad, "not a node header");
  bad = good;
  // A pointer of the root to one of its grandchildren (a node one level too far down).
  const uint32_t child = good.words[root_ptr];
  const uint32_t grandchild = good.words[child + __builtin_popcount(good.words[child] & 0xffu)];
  bad.words[root_ptr] = grandchild;
  EXPECT_THROW(level_order_stream(bad, 64), Error);
  // Padding that is not zero, or a node nobody reaches.
  bad = good;
  std::vector<bool> reached(good.words.size(), false);
  uint64_t pad = 0;
  for (size_t k = 0; k < lay.at.size(); ++k) {
    const uint64_t end = k + 1 < lay.old_at.size() ? lay.old_at[k + 1] : enc.words.size();
    for (uint64_t q = lay.at[k]; q < lay.at[k] + end - lay.old_at[k]; ++q) reached[q] = true;
  }
  while (pad < reached.size() && reached[pad]) ++pad;
  if (pad < reached.size()) {
    bad.words[pad] = 7;
    expect_error(bad, "neither in a node");
  }
  // Read with smaller pages than it was made with: some node crosses a boundary.
  expect_error(good, "crosses a page boundary", 16);
  bad = good;
  bad.words.resize(good.words.size() / 2);
  EXPECT_THROW(level_order_stream(bad, 64), Error);
  bad = good;
  bad.levels = 22;
  expect_error(bad, "level count");
  bad = good;
  bad.levels = 5;  // one level short: level-1 masks read as inner headers or pointers go astray
  EXPECT_THROW(level_order_stream(bad, 64), Error);
  // Random damage: an error or a valid stream, nothing in between (and no read out of bounds under ASan).
  std::mt19937_64 rng(3);
  for (int i = 0; i < 3000; ++i) {
    bad = good;
    for (int f = 0; f < 1 + i % 3; ++f) {
      uint32_t& w = bad.words[rng() % bad.words.size()];
      w = i % 2 ? w ^ (1u << (rng() % 32)) : static_cast<uint32_t>(rng() % (bad.words.size() + 16));
    }
    try {
      const EncodedDag back = level_order_stream(bad, 64);
      ASSERT_NO_THROW(validate_svdag(back));
      ASSERT_LE(back.words.size(), bad.words.size());
    } catch (const Error&) {
    }
  }
}

// Level order: each pointer counts from its child level's start, which level_offset holds (64-bit), so the
// pointers stay small however far down the stream a level starts.
TEST(PagedStream, LevelOrderPointersCountFromTheirLevel) {
  const EncodedDag enc = encode_svdag(host_dag(voxel_sets(6)[0].second, 6, true));
  const PageLayout lay = page_layout(enc, NodeOrder::level, 64);
  const EncodedDag good = paged_stream(enc, lay);
  const uint32_t L = good.levels;
  ASSERT_EQ(good.level_offset.size(), L + 1u);
  EXPECT_EQ(good.level_offset[L], 0u);
  for (uint32_t l = 2; l <= L; ++l) EXPECT_GT(good.level_offset[l - 1], good.level_offset[l]);
  const uint32_t root_ptr = __builtin_popcount(good.words[0] & 0xffu);  // its first child in Morton order
  EXPECT_EQ(good.level_offset[L - 1] + good.words[root_ptr], good.level_offset[L - 1]);  // the level's first node
  auto expect_error = [&](const EncodedDag& bad, const std::string& words) {
    const std::string why = error_message([&] { level_order_stream(bad, 64); });
    EXPECT_NE(why.find(words), std::string::npos) << "'" << why << "' lacks '" << words << "'";
  };
  EncodedDag bad = good;
  bad.words[root_ptr] = static_cast<uint32_t>(good.level_offset[L - 2] - good.level_offset[L - 1]);  // its level's end
  expect_error(bad, "past the end of level");
  bad = good;
  bad.level_offset[L] = 1;  // the root not at word 0
  expect_error(bad, "bad level starts");
  bad = good;
  std::swap(bad.level_offset[2], bad.level_offset[3]);  // out of order
  expect_error(bad, "bad level starts");
  bad = good;
  bad.level_offset.pop_back();
  expect_error(bad, "bad level starts");
  bad = good;
  bad.level_offset[1] = good.words.size();  // an empty last level
  expect_error(bad, "bad level starts");
  // The same stream read as absolute pointers goes astray: the starts are what makes it valid.
  bad = good;
  bad.level_offset.clear();
  EXPECT_THROW(level_order_stream(bad, 64), Error);
}

}  // namespace
}  // namespace mv::test
