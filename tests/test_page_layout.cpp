// Node orders for paging (host/formats/paging/page_layout.h) on host-built octrees and DAGs: every node in exactly one
// page and none overlapping, level order with large pages is the stream itself, padding stays small, the
// subtree order reads fewer pages per descent, and what cannot be paged is a clear error.
#include <algorithm>
#include <map>
#include <random>

#include "paging/page_layout.h"
#include "test_support.h"

namespace mv::test {
namespace {

void expect_valid(const EncodedDag& enc, const PageLayout& lay) {
  std::vector<std::pair<uint64_t, uint64_t>> spans;  // (new start, size)
  for (size_t k = 0; k < lay.at.size(); ++k) {
    const uint64_t end = k + 1 < lay.old_at.size() ? lay.old_at[k + 1] : enc.words.size();
    const uint64_t size = end - lay.old_at[k];
    ASSERT_EQ(lay.at[k] / lay.page_words, (lay.at[k] + size - 1) / lay.page_words) << "node " << k << " split";
    spans.push_back({lay.at[k], size});
  }
  std::sort(spans.begin(), spans.end());
  for (size_t k = 1; k < spans.size(); ++k) ASSERT_GE(spans[k].first, spans[k - 1].first + spans[k - 1].second);
  ASSERT_EQ(lay.words, spans.back().first + spans.back().second);
}

TEST(PageLayout, EveryNodeInOnePage) {
  for (auto& [name, voxels] : voxel_sets(7)) {
    for (bool reduce : {false, true}) {
      const EncodedDag enc = encode_svdag(host_dag(voxels, 7, reduce));
      const uint32_t whole = std::max<uint32_t>(9, static_cast<uint32_t>(enc.words.size()));  // one page
      for (NodeOrder o : {NodeOrder::level, NodeOrder::subtree}) {
        for (uint32_t pw : {9u, 10u, 64u, 1000u, whole}) {
          SCOPED_TRACE(name + (reduce ? " dag " : " svo ") + node_order_name(o) + " " + std::to_string(pw));
          const PageLayout lay = page_layout(enc, o, pw);
          ASSERT_EQ(lay.at.size(), lay.old_at.size());
          expect_valid(enc, lay);
          if (pw >= 1000) {
            EXPECT_LE(lay.words, enc.words.size() * 1.01);  // at most 8 padding words a page
          }
          if (pw == whole) {
            EXPECT_EQ(lay.words, enc.words.size());  // one page: no padding
          }
          if (o == NodeOrder::level && pw == whole) {
            EXPECT_TRUE(std::equal(lay.at.begin(), lay.at.end(), lay.old_at.begin()));
          }
          const PageLayoutStats st = measure_page_layout(enc, lay, 200, 3);
          EXPECT_EQ(st.pages, lay.pages());
          EXPECT_LE(st.max_pages_per_path, enc.levels);
          EXPECT_GE(st.pages_per_path, 1.0);
        }
      }
    }
  }
}

// The reason for the subtree order: on a deep octree with small pages, a descent in level order meets a new
// page at nearly every level; subtree pages hold several levels of a path.
TEST(PageLayout, SubtreeOrderReadsFewerPagesPerDescent) {
  std::mt19937_64 rng(12);
  std::vector<uint64_t> voxels;  // 20000 random voxels of a 4096^3 grid: long, thin paths below the top levels
  for (int i = 0; i < 20000; ++i) voxels.push_back(rng() & ((uint64_t{1} << 36) - 1));
  const EncodedDag enc = encode_svdag(host_dag(sorted_unique(voxels), 12, false));
  const PageLayoutStats lv = measure_page_layout(enc, page_layout(enc, NodeOrder::level, 256), 2000, 5);
  const PageLayoutStats st = measure_page_layout(enc, page_layout(enc, NodeOrder::subtree, 256), 2000, 5);
  EXPECT_LT(st.pages_per_path, 0.6 * lv.pages_per_path) << st.pages_per_path << " vs " << lv.pages_per_path;
  EXPECT_LT(st.crossing, lv.crossing);
  EXPECT_LE(st.size_ratio, 1.05);
}

TEST(PageLayout, UnpageableInputsAreClearErrors) {
  const EncodedDag enc = encode_svdag(host_dag({1, 9, 300}, 4, false));
  EXPECT_NE(error_message([&] { page_layout(enc, NodeOrder::subtree, 8); }).find("cannot hold a node"),
            std::string::npos);
  EncodedDag ss;
  ss.encoding = Encoding::ssvdag;
  EXPECT_NE(error_message([&] { page_layout(ss, NodeOrder::level, 4096); }).find("ssvdag"), std::string::npos);
  EncodedDag bad = enc;
  bad.words[1] = 12345;  // a pointer to no node
  EXPECT_NE(error_message([&] { page_layout(bad, NodeOrder::level, 4096); }).find("svdag"), std::string::npos);
}

}  // namespace
}  // namespace mv::test
