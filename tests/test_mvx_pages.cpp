// The paged .mvx (version 3 on): every 32-bit encoding written paged and read back in level order, the paging
// options, version 2 files still opening, MvxPages reading single pages from the mapped file (checked, thread
// safe, failing cleanly on injected faults), and hand-made damage to the page index and the pages, with every
// checksum made right so that the structure checks behind them are what answers.
#include <xxhash.h>

#include <cstring>
#include <filesystem>
#include <functional>
#include <fstream>
#include <thread>

#include "paging/paged_ssvdag.h"
#include "paging/paged_stream.h"
#include "io/file_ops.h"
#include "io/mvx_format.h"
#include "io/mvx_pages.h"
#include "megavox/mvx.h"
#include "megavox/trace.h"
#include "test_support.h"

namespace mv::test {
namespace {

namespace fs = std::filesystem;
namespace fmt = mvx_format;

MvxFile file_of(const EncodedDag& enc, const Dag& dag) {
  MvxFile f;
  f.grid.resolution = 1u << dag.levels;
  f.grid.voxel_size = 0.25;
  f.grid.origin[1] = 2;
  f.bounds.extend(0, 2, 0);
  f.bounds.extend(4, 6, 3);
  f.voxels = dag.voxels;
  f.svo_nodes = dag.svo_nodes.empty() ? std::vector<uint64_t>(dag.levels + 1, 0) : dag.svo_nodes;
  f.dag_nodes.push_back(dag.voxels);
  for (uint32_t l = 1; l <= dag.levels; ++l) f.dag_nodes.push_back(dag.level[l].mask.size());
  f.dag = enc;
  return f;
}

// A 2^6 DAG of every 32-bit encoding (the ussvdag: the svdag with mirror bits on the root's pointers).
std::vector<MvxFile> sample_files() {
  const std::vector<uint64_t> voxels = voxel_sets(6)[1].second;  // the shell
  const Dag svo = host_dag(voxels, 6, false), dag = host_dag(voxels, 6, true);
  EncodedDag us = encode_svdag(dag);
  us.encoding = Encoding::ussvdag;
  us.words[0] |= (us.words[0] & 0xffu) << 8;  // X mirror on every child of the root
  return {file_of(encode_svdag(svo), svo), file_of(encode_svdag(dag), dag), file_of(us, dag)};
}

// A written file's bytes with its header and section table at hand, to damage and then make every checksum
// right again (checked sections, the page index's page hashes, the header).
struct Bytes {
  std::vector<char> b;
  fmt::Header h{};
  explicit Bytes(const std::string& p) : b(file_bytes(p)) { std::memcpy(&h, b.data(), sizeof h); }
  fmt::Section& section(uint32_t kind) {
    for (uint32_t i = 0; i < h.sections; ++i)
      if (h.table[i].kind == kind) return h.table[i];
    throw Error("no section of kind " + std::to_string(kind));
  }
  template <class T>
  T* at(uint32_t kind, uint64_t byte = 0) { return reinterpret_cast<T*>(b.data() + section(kind).offset + byte); }
  void rehash_pages() {  // as far as the index is sane enough to say where the pages are
    fmt::PageIndexHead head;
    std::memcpy(&head, at<char>(fmt::kPageIndex), sizeof head);
    const uint64_t words = section(fmt::kNodes).bytes / 4;
    if (head.page_words < 16 || (head.page_words & (head.page_words - 1)) || head.page_words > (1u << 24)) return;
    const uint64_t room = (section(fmt::kPageIndex).bytes - 24) / 8;
    for (uint64_t p = 0; p < std::min(head.pages, room) && p * head.page_words < words; ++p)
      at<uint64_t>(fmt::kPageIndex, 24)[p] = fmt::page_hash(at<uint32_t>(fmt::kNodes) + p * head.page_words,
                                                            std::min<uint64_t>(head.page_words, words - p * head.page_words),
                                                            head.page_words);
  }
  void write(const std::string& p) {
    for (uint32_t i = 0; i < h.sections; ++i) {
      fmt::Section& s = h.table[i];
      if (s.kind != fmt::kNodes || !find_index()) s.checksum = fmt::hash(b.data() + s.offset, s.bytes);
    }
    h.checksum = fmt::hash(&h, offsetof(fmt::Header, checksum));
    std::memcpy(b.data(), &h, sizeof h);
    write_bytes(p, b);
  }
  bool find_index() const {
    for (uint32_t i = 0; i < h.sections; ++i)
      if (h.table[i].kind == fmt::kPageIndex) return true;
    return false;
  }
};

TEST(MvxPaged, EveryEncodingAndPagingReadsBackInLevelOrder) {
  const std::string p = temp_path("paged.mvx");
  for (const MvxFile& f : sample_files()) {
    const std::vector<uint64_t> voxels = decode_encoded(f.dag);
    for (MvxPaging paging : {MvxPaging{}, MvxPaging{16, NodeOrder::subtree}, MvxPaging{64, NodeOrder::level},
                             MvxPaging{0, NodeOrder::level}}) {
      SCOPED_TRACE(encoding_name(f.dag.encoding) + " " + std::to_string(paging.page_words) + " " +
                   node_order_name(paging.order));
      write_mvx(p, f, paging);
      const MvxFile g = read_mvx(p);
      EXPECT_EQ(g.dag.encoding, f.dag.encoding);
      EXPECT_EQ(g.dag.level_offset, f.dag.level_offset);
      EXPECT_EQ(g.dag.words.size(), f.dag.words.size());
      EXPECT_TRUE(decode_encoded(g.dag) == voxels);
      EXPECT_EQ(g.dag_nodes, f.dag_nodes);
      EXPECT_EQ(g.grid.voxel_size, 0.25);
      EXPECT_EQ(g.paging.page_words, paging.page_words);
      if (paging.page_words) {
        EXPECT_EQ(g.paging.order, paging.order);
        EXPECT_GE(g.paged_words, f.dag.words.size());
        // Read and written again, twice: the same bytes (what is read is in the order the way back discovers).
        write_mvx(p, g, paging);
        const std::vector<char> once = file_bytes(p);
        write_mvx(p, read_mvx(p), paging);
        EXPECT_EQ(file_bytes(p), once);
      } else {
        EXPECT_TRUE(g.dag.words == f.dag.words);
      }
      Bytes b(p);
      EXPECT_EQ(b.h.version, kMvxVersion);
      EXPECT_EQ(b.find_index(), paging.page_words != 0);
    }
  }
  // Only powers of two from 16 words are written.
  for (uint32_t pw : {9u, 48u, 1u << 25})
    EXPECT_NE(error_message([&] { write_mvx(p, sample_files()[1], {pw, NodeOrder::subtree}); }).find("power of two"),
              std::string::npos);
  fs::remove(p);
}

TEST(MvxPaged, VersionTwoFilesStillOpen) {
  // A version 2 voxel file is a version 3 unpaged one with 2 in the version field.
  const MvxFile f = sample_files()[1];
  const std::string p = temp_path("v2.mvx");
  write_mvx(p, f, {0, NodeOrder::level});
  Bytes b(p);
  b.h.version = 2;
  b.write(p);
  const MvxFile g = read_mvx(p);
  EXPECT_TRUE(g.dag.words == f.dag.words);
  EXPECT_EQ(g.paging.page_words, 0u);
  EXPECT_NE(error_message([&] { MvxPages pages(p); }).find("renders resident"), std::string::npos);
  // A page index in a version 2 file is damage.
  write_mvx(p, f);
  Bytes c(p);
  c.h.version = 2;
  c.write(p);
  EXPECT_NE(error_message([&] { read_mvx(p); }).find("page index in a version 2"), std::string::npos);
  fs::remove(p);
}

TEST(MvxPaged, PagesReadAloneMakeTheStream) {
  const std::string p = temp_path("pages.mvx");
  for (const MvxFile& f : sample_files()) {
    write_mvx(p, f, {16, NodeOrder::subtree});
    const MvxPages pages(p);
    EXPECT_EQ(pages.encoding(), f.dag.encoding);
    EXPECT_EQ(pages.levels(), 6u);
    EXPECT_EQ(pages.page_words(), 16u);
    EXPECT_EQ(pages.order(), NodeOrder::subtree);
    EXPECT_EQ(pages.grid().resolution, 64u);
    EXPECT_EQ(pages.bounds().hi[2], 3);
    EXPECT_EQ(pages.voxels(), f.voxels);
    EXPECT_EQ(pages.pages(), (pages.words() + 15) / 16);
    ASSERT_GT(pages.pages(), 4u);
    // Every page, read on two threads at once, together makes the paged stream.
    EncodedDag paged;
    paged.encoding = f.dag.encoding;
    paged.levels = f.dag.levels;
    paged.words.assign(uint64_t{pages.pages()} * 16, 0);
    std::vector<std::string> errors(2);
    std::vector<std::thread> threads;
    for (uint32_t t = 0; t < 2; ++t)
      threads.emplace_back([&, t] {
        for (uint32_t page = t; page < pages.pages(); page += 2)
          if (!pages.read_page(page, std::span<uint32_t>(paged.words.data() + page * 16, 16), &errors[t])) return;
      });
    for (auto& t : threads) t.join();
    EXPECT_EQ(errors[0] + errors[1], "");
    paged.words.resize(pages.words());
    EXPECT_TRUE(level_order_stream(paged, 16).words == read_mvx(p).dag.words);
    std::vector<uint32_t> page(16), small(8);
    std::string error;
    EXPECT_FALSE(pages.read_page(pages.pages(), page, &error));
    EXPECT_NE(error.find("past the end"), std::string::npos) << error;
    EXPECT_FALSE(pages.read_page(0, small, &error));
    EXPECT_NE(error.find("buffer of 8 words"), std::string::npos) << error;
    // The last page comes zero-padded.
    std::fill(page.begin(), page.end(), 0xdeadbeefu);
    ASSERT_TRUE(pages.read_page(pages.pages() - 1, page, &error)) << error;
    for (uint64_t w = pages.words() % 16; w && w < 16; ++w) EXPECT_EQ(page[w], 0u);
  }
  fs::remove(p);
}

TEST(MvxPaged, PageReadsFailCleanly) {
  const std::string p = temp_path("faults.mvx");
  write_mvx(p, sample_files()[0], {16, NodeOrder::subtree});
  {
    const MvxPages pages(p);
    std::vector<uint32_t> page(16);
    std::string error;
    io::faults::arm(io::faults::Kind::kMappedRead, 2);
    EXPECT_TRUE(pages.read_page(0, page, &error));
    EXPECT_TRUE(pages.read_page(1, page, &error));
    EXPECT_FALSE(pages.read_page(2, page, &error));  // the injected fault
    EXPECT_TRUE(io::faults::fired());
    io::faults::disarm();
    EXPECT_NE(error.find("page 2: read error"), std::string::npos) << error;
    EXPECT_TRUE(pages.read_page(2, page, &error)) << error;  // the page is still there: a retry reads it
  }
  // A flip inside one page: that page fails its hash, the others read. read_mvx names the page.
  Bytes b(p);
  b.at<uint32_t>(fmt::kNodes)[3 * 16 + 5] ^= 0x100;
  write_bytes(p, b.b);  // checksums as they were
  const MvxPages pages(p);
  std::vector<uint32_t> page(16);
  std::string error;
  EXPECT_TRUE(pages.read_page(2, page, &error));
  EXPECT_FALSE(pages.read_page(3, page, &error));
  EXPECT_NE(error.find("page 3: checksum mismatch"), std::string::npos) << error;
  EXPECT_NE(error_message([&] { read_mvx(p); }).find("checksum mismatch in page 3"), std::string::npos);
  fs::remove(p);
}

// A file truncated by someone else while it is mapped (a download restarted, a build writing over it in
// place): the pages past its new end raise SIGBUS on access, which a page read turns into a clear failure.
TEST(MvxPaged, AFileTruncatedWhileMappedFailsItsReads) {
  const std::string p = temp_path("shrunk.mvx");
  write_mvx(p, sample_files()[0], {16, NodeOrder::subtree});
  const MvxPages pages(p);
  std::vector<uint32_t> page(16);
  std::string error;
  ASSERT_TRUE(pages.read_page(1, page, &error)) << error;
  fs::resize_file(p, 0);  // every mapped page now lies past the end
  for (uint32_t i = 0; i < 2; ++i) {  // twice: the guard is reset after a caught fault
    EXPECT_FALSE(pages.read_page(i, page, &error));
    EXPECT_NE(error.find("page " + std::to_string(i) + ": the file is shorter than when it was opened"), std::string::npos)
        << error;
  }
  fs::remove(p);
}

// Damage to the page index or the pages under right checksums: each a clear error from read_mvx (and from
// MvxPages where it reads what is damaged).
TEST(MvxPaged, PageIndexDamageIsAClearError) {
  const std::string p = temp_path("index.mvx"), q = temp_path("index_damaged.mvx");
  const MvxFile f = sample_files()[1];
  write_mvx(p, f, {16, NodeOrder::subtree});
  auto expect = [&](const std::function<void(Bytes&)>& damage, const std::string& words, bool pages_too) {
    Bytes b(p);
    damage(b);
    b.write(q);
    const std::string why = error_message([&] { read_mvx(q); });
    EXPECT_NE(why.find(words), std::string::npos) << "'" << why << "' lacks '" << words << "'";
    if (pages_too) {
      const std::string why_pages = error_message([&] { MvxPages pages(q); });
      EXPECT_NE(why_pages.find(words), std::string::npos) << "'" << why_pages << "' lacks '" << words << "'";
    }
  };
  auto head = [](Bytes& b) { return b.at<fmt::PageIndexHead>(fmt::kPageIndex); };
  expect([](Bytes& b) { b.section(fmt::kPageIndex).bytes = 20; }, "bad page index: truncated", true);
  expect([](Bytes& b) { b.section(fmt::kPageIndex).bytes -= 8; }, "page hashes for", true);
  expect([&](Bytes& b) { head(b)->page_words = 24; }, "pages of 24 words", true);
  expect([&](Bytes& b) { head(b)->page_words = 8; }, "pages of 8 words", true);
  expect([&](Bytes& b) { head(b)->page_words = 0; }, "pages of 0 words", true);
  expect([&](Bytes& b) { head(b)->order = 2; }, "unknown node order", true);
  expect([&](Bytes& b) { head(b)->words += 1; }, "but the nodes section holds", true);
  expect([&](Bytes& b) { head(b)->pages -= 1; }, "cannot hold", true);
  expect([&](Bytes& b) { head(b)->pages += 1; }, "an empty page at the end", true);
  expect([&](Bytes& b) { head(b)->pages = ~uint64_t{0} / 16; }, "an empty page at the end", true);
  expect([&](Bytes& b) { head(b)->pages = 0; }, "cannot hold", true);
  // Raw checksum damage: a page's hash, the index's own checksum.
  {
    Bytes b(p);
    b.at<uint64_t>(fmt::kPageIndex, 24)[1] ^= 1;
    b.write(q);
    EXPECT_NE(error_message([&] { read_mvx(q); }).find("checksum mismatch in page 1"), std::string::npos);
    b.section(fmt::kPageIndex).checksum ^= 1;
    b.h.checksum = fmt::hash(&b.h, offsetof(fmt::Header, checksum));
    std::memcpy(b.b.data(), &b.h, sizeof b.h);
    write_bytes(q, b.b);
    EXPECT_NE(error_message([&] { MvxPages pages(q); }).find("checksum mismatch in the page index"), std::string::npos);
  }
  // The structure behind right page hashes: a pointer leaving the stream, into a node, a header gone, a node
  // across a page (pages said to be smaller than written), levels that disagree.
  auto pointer_damage = [&](uint32_t value) {
    return [=](Bytes& b) {
      uint32_t* w = b.at<uint32_t>(fmt::kNodes);
      w[__builtin_popcount(w[0] & 0xffu)] = value;
      b.rehash_pages();
    };
  };
  const uint32_t words = static_cast<uint32_t>(Bytes(p).section(fmt::kNodes).bytes / 4);
  expect(pointer_damage(words + 100), "past the end", false);
  expect(pointer_damage(1), "not the start of a node", false);
  expect([](Bytes& b) { b.at<uint32_t>(fmt::kNodes)[0] = 0; b.rehash_pages(); }, "not a node header", false);
  {
    // Written with 64-word pages, declared 16: counts fixed, hashes made for 16 words: a node crosses.
    write_mvx(q, f, {64, NodeOrder::subtree});
    Bytes b(q);
    fmt::PageIndexHead h = *head(b);
    h.page_words = 16;
    h.pages = (h.words + 15) / 16;
    std::vector<char> index(24 + h.pages * 8);
    std::memcpy(index.data(), &h, 24);
    fmt::Section& s = b.section(fmt::kPageIndex);
    ASSERT_LE(index.size(), 4096u);
    std::memcpy(b.b.data() + s.offset, index.data(), index.size());
    s.bytes = index.size();
    b.rehash_pages();
    b.write(q);
    EXPECT_NE(error_message([&] { read_mvx(q); }).find("crosses a page boundary"), std::string::npos);
  }
  expect([](Bytes& b) { b.at<uint64_t>(fmt::kLevels)[1] += 1; }, "disagree with the levels section", false);
  // Every single-byte flip anywhere, checksums made right: an error or the same voxels.
  const std::vector<uint64_t> voxels = decode_encoded(f.dag);
  const Bytes good(p);
  for (size_t i = 4096; i < good.b.size(); i += 13) {
    Bytes b = good;
    b.b[i] ^= 0x21;
    if (b.find_index()) b.rehash_pages();
    b.write(q);
    try {
      const MvxFile g = read_mvx(q);
      EXPECT_NO_THROW(validate_encoded(g.dag));
    } catch (const Error&) {
    }
  }
  fs::remove(p);
  fs::remove(q);
}

// An ssvdag is written paged in its own layout (level order, paged_ssvdag.h) with its level starts, reads back
// byte for byte at every page size, streams page by page, and says so when its starts are damaged.
TEST(MvxPaged, SsvdagIsPagedInLevelOrder) {
  const std::string p = temp_path("paged_ssvdag.mvx");
  const std::vector<uint64_t> voxels = voxel_sets(6)[0].second;  // random: many nodes
  const Dag dag = host_dag(voxels, 6, true);
  const MvxFile f = file_of(encode_ssvdag(dag), dag);
  for (MvxPaging paging : {MvxPaging{}, MvxPaging{16, NodeOrder::subtree}, MvxPaging{64, NodeOrder::level}}) {
    SCOPED_TRACE(std::to_string(paging.page_words));
    write_mvx(p, f, paging);
    ASSERT_TRUE(Bytes(p).find_index());
    const MvxFile g = read_mvx(p);
    EXPECT_TRUE(g.dag.inner == f.dag.inner && g.dag.bricks == f.dag.bricks);
    EXPECT_EQ(g.dag.level_offset, f.dag.level_offset);
    EXPECT_EQ(g.paging.page_words, paging.page_words);
    EXPECT_EQ(g.paging.order, NodeOrder::level);  // whatever was asked for
    const MvxPages pages(p);
    ASSERT_EQ(pages.level_starts().size(), 7u);
    std::vector<uint32_t> words(uint64_t{pages.pages()} * paging.page_words);
    std::string error;
    for (uint32_t pg = 0; pg < pages.pages(); ++pg)
      ASSERT_TRUE(pages.read_page(pg, std::span<uint32_t>(words.data() + uint64_t{pg} * paging.page_words, paging.page_words), &error)) << error;
    words.resize(pages.words());
    const EncodedDag back = ssvdag_from_pages(words, pages.level_starts(), 6, paging.page_words);
    EXPECT_TRUE(back.inner == f.dag.inner && back.bricks == f.dag.bricks);
  }
  // Damaged starts, checksums made right: the structure check or MvxPages names them.
  write_mvx(p, f, {16, NodeOrder::level});
  Bytes b(p);
  b.at<uint64_t>(fmt::kPagedStarts)[4] = b.at<uint64_t>(fmt::kPagedStarts)[6] + 2;
  b.write(p);
  EXPECT_NE(error_message([&] { MvxPages pages(p); }).find("bad paged level starts"), std::string::npos);
  EXPECT_NE(error_message([&] { read_mvx(p); }).find("out of order"), std::string::npos);
  // Unpaged, it renders resident and says so.
  write_mvx(p, f, {0, NodeOrder::level});
  EXPECT_FALSE(Bytes(p).find_index());
  EXPECT_TRUE(read_mvx(p).dag.inner == f.dag.inner);
  EXPECT_NE(error_message([&] { MvxPages pages(p); }).find("renders resident"), std::string::npos);
  // An empty ssvdag (no voxels) pages to no pages.
  MvxFile e = f;
  e.dag.inner.clear();
  e.dag.bricks.clear();
  e.dag.level_offset.assign(7, 0);
  e.voxels = 0;
  write_mvx(p, e);
  EXPECT_TRUE(read_mvx(p).dag.inner.empty());
  fs::remove(p);
}

// A paged file with colours carries its size plane (version 5): damage to the plane, to its index or to which
// sections a version has is named; a page of the plane read alone is checked by its own hash.
TEST(MvxPaged, TheSizePlaneIsCheckedPageByPageAndAgainstTheNodes) {
  const std::string p = temp_path("sized.mvx"), q = temp_path("sized_damaged.mvx");
  MvxFile f = sample_files()[1];
  f.svo_nodes = encoded_octree_nodes(f.dag);
  uint64_t entries = 0;
  for (uint64_t n : f.svo_nodes) entries += n;
  for (uint64_t e = 0; e < entries; ++e) f.colours.insert(f.colours.end(), {uint8_t(e), uint8_t(e >> 8), 7});
  f.colour_storage = ColourStorage::raw;
  write_mvx(p, f, {16, NodeOrder::subtree});
  const MvxPages pages(p);
  ASSERT_EQ(pages.plane_words(), 16u);
  EXPECT_EQ(pages.colour_entries(), entries);
  EXPECT_EQ(pages.colour(entries - 1), (uint32_t((entries - 1) & 255) | uint32_t(((entries - 1) >> 8) & 255) << 8 | 7u << 16));
  EXPECT_THROW(pages.colour(entries), Error);
  std::vector<uint32_t> plane(16);
  std::string error;
  ASSERT_TRUE(pages.read_sizes(0, plane, &error)) << error;
  EXPECT_NE(plane[1], 0u);  // the root's first pointer holds its child's subtree size
  auto damaged = [&](const std::function<void(Bytes&)>& hurt) {
    Bytes b(p);
    hurt(b);
    b.write(q);
    return error_message([&] { read_mvx(q); });
  };
  // a size off by one, its page hash made right: only the check against the nodes sees it
  EXPECT_NE(damaged([](Bytes& b) {
              uint32_t* sizes = b.at<uint32_t>(fmt::kSizes);
              sizes[1] += 1;
              auto* hashes = b.at<uint64_t>(fmt::kSizeIndex, sizeof(fmt::SizeIndexHead));
              hashes[0] = fmt::page_hash(sizes, 16, 16);
            }).find("size plane disagrees"), std::string::npos);
  // the same without the hash made right: read whole or read alone, the page fails its hash
  EXPECT_NE(damaged([](Bytes& b) { b.at<uint32_t>(fmt::kSizes)[1] += 1; }).find("page 0 of the size plane"),
            std::string::npos);
  EXPECT_FALSE(MvxPages(q).read_sizes(0, plane, &error));
  EXPECT_NE(error.find("checksum"), std::string::npos) << error;
  EXPECT_NE(damaged([](Bytes& b) { b.at<fmt::SizeIndexHead>(fmt::kSizeIndex)->plane_words = 32; }).find("bad size index"),
            std::string::npos);
  EXPECT_NE(damaged([](Bytes& b) { b.h.version = 4; }).find("bad section table"), std::string::npos);
  // a version 4 file with colours (no plane) still opens; it streams without them
  write_mvx(p, f, {0, NodeOrder::level});  // (unpaged: no plane) marked version 4 for the check
  Bytes old(p);
  old.h.version = 4;
  old.write(q);
  EXPECT_EQ(read_mvx(q).colours, f.colours);
  fs::remove(p);
  fs::remove(q);
}

// A damaged file whose checksums are right (made so): the root's pointers lead past the pages. Streamed, no ray
// reads outside the cache (the walk never resolves such a pointer: it stops coarse there), with a cache of every
// page (preloaded) and with a small one, on every device.
class MvxPagedDamageTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST_P(MvxPagedDamageTest, PointersPastThePagesNeverResolve) {
  const std::string p = temp_path("far.mvx"), q = temp_path("far_damaged.mvx");
  const MvxFile f = sample_files()[1];
  write_mvx(p, f, {16, NodeOrder::subtree});
  Bytes b(p);
  uint32_t* words = b.at<uint32_t>(fmt::kNodes);
  for (int c = 0; c < __builtin_popcount(words[0] & 0xffu); ++c) words[1 + c] = 0x7ffffff0u - 16u * uint32_t(c);
  b.rehash_pages();
  b.write(q);
  for (uint64_t cache : {uint64_t{1} << 20, uint64_t{4} * 64}) {
    SCOPED_TRACE(cache);
    Tracer t(shared_device(GetParam()), open_paged_mvx(q), cache);
    std::vector<Ray> rays;
    for (int i = 0; i < 64; ++i) rays.push_back(Ray{{0.5f + 0.25f * float(i % 8) * 8, 2.5f + 0.25f * float(i / 8) * 8, -5}, {0, 0, 1}});
    for (const RayHit& h : t.trace(rays)) EXPECT_TRUE(!h.hit || h.coarse);
  }
}

// A word stream paged in level order is written with relative pointers and its level starts (version 5); the
// same stream with absolute pointers and no starts (how version 4 wrote it) still opens, reads back and
// streams, tracing as the resident DAG does. Starts where the version or order has none, or none where they
// are needed, are damage.
TEST_P(MvxPagedDamageTest, VersionFourLevelOrderFilesKeepTheirAbsolutePointers) {
  const std::string p = temp_path("relative.mvx"), q = temp_path("absolute.mvx");
  const MvxFile f = sample_files()[1];
  write_mvx(p, f, {16, NodeOrder::level});
  Bytes b(p);
  ASSERT_EQ(b.h.version, kMvxVersion);
  const uint32_t L = f.dag.levels;
  const std::vector<uint64_t> starts(b.at<uint64_t>(fmt::kPagedStarts), b.at<uint64_t>(fmt::kPagedStarts) + L + 1);
  EXPECT_EQ(MvxPages(p).level_starts(), starts);
  // Every pointer made absolute (the headers are non-zero, the padding zero), the starts section dropped.
  std::vector<uint32_t> nodes(b.at<uint32_t>(fmt::kNodes), b.at<uint32_t>(fmt::kNodes) + b.section(fmt::kNodes).bytes / 4);
  for (uint32_t l = L; l >= 2; --l)
    for (uint64_t w = starts[l]; w < starts[l - 1];) {
      if (nodes[w] == 0) {
        ++w;
        continue;
      }
      const uint32_t size = 1 + __builtin_popcount(nodes[w] & 0xffu);
      for (uint32_t k = 1; k < size; ++k) nodes[w + k] += static_cast<uint32_t>(starts[l - 1]);
      w += size;
    }
  std::vector<uint64_t> index(b.at<uint64_t>(fmt::kPageIndex), b.at<uint64_t>(fmt::kPageIndex) + b.section(fmt::kPageIndex).bytes / 8);
  for (uint64_t pg = 0; pg + 3 < index.size(); ++pg)
    index[3 + pg] = fmt::page_hash(nodes.data() + pg * 16, std::min<uint64_t>(16, nodes.size() - pg * 16), 16);
  auto write_as = [&](uint32_t version, bool with_starts) {
    fmt::Header h = b.h;
    h.version = version;
    std::vector<fmt::Blob> blobs = {{fmt::kCounts, b.at<char>(fmt::kCounts), b.section(fmt::kCounts).bytes},
                                    {fmt::kLevels, b.at<char>(fmt::kLevels), b.section(fmt::kLevels).bytes},
                                    {fmt::kNodes, nodes.data(), nodes.size() * 4, false},
                                    {fmt::kPageIndex, index.data(), index.size() * 8}};
    if (with_starts) blobs.push_back({fmt::kPagedStarts, starts.data(), starts.size() * 8});
    fmt::write_file(q, h, blobs);
  };
  write_as(4, false);
  EXPECT_TRUE(MvxPages(q).level_starts().empty());
  EXPECT_TRUE(read_mvx(q).dag.words == f.dag.words);
  std::vector<Ray> rays;
  for (int i = 0; i < 256; ++i)
    rays.push_back(Ray{{0.3f + 0.25f * float(i % 16) * 1.2f, 2.2f + 0.25f * float(i / 16) * 1.2f, -5}, {0.05f, 0.02f, 1}});
  Device& dev = shared_device(GetParam());
  const std::vector<RayHit> want = Tracer(dev, f).trace(rays);
  const uint64_t half = MvxPages(p).pages() / 2 * 64;  // the pages' bytes, halved: they stream
  for (const std::string& file : {p, q})
    for (uint64_t cache : {uint64_t{1} << 20, half}) {  // every page (preloaded), or half of them
      SCOPED_TRACE(file + " " + std::to_string(cache));
      Tracer t(dev, open_paged_mvx(file), cache);
      EXPECT_GT(expect_same_hits(t.trace(rays), want), 0u);
      EXPECT_EQ(t.last_passes().size() > 1, cache == half);
    }
  write_as(4, true);  // starts in a version 4 file
  EXPECT_NE(error_message([&] { read_mvx(q); }).find("bad section table"), std::string::npos);
  write_as(5, false);  // a version 5 level-order stream without them
  EXPECT_NE(error_message([&] { MvxPages pages(q); }).find("paged level starts missing"), std::string::npos);
  EXPECT_NE(error_message([&] { read_mvx(q); }).find("paged level starts missing"), std::string::npos);
  fs::remove(p);
  fs::remove(q);
}

MV_INSTANTIATE_ON_ALL_DEVICES(MvxPagedDamageTest);

}  // namespace
}  // namespace mv::test
