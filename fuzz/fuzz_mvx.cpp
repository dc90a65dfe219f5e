// The .mvx readers (include/megavox/mvx.h): read_mvx, read_mvx_points and MvxPages (a paged file's pages, its
// size plane's pages and its colour entries read one by one) on the same bytes.
//
// Every section, every page of paged nodes and the header carry an XXH3 checksum, which random mutations
// almost never keep right; so each input is read twice: as it is (the checksum checks), and with its
// checksums recomputed over what its section table and page index point at (what lies behind them: the
// sizes, the counts, the paged stream's structure, the encoding's validation).
#include <algorithm>
#include <cstddef>
#include <cstring>
#include <vector>

#include "fuzz_support.h"
#include "io/mvx_format.h"
#include "io/mvx_pages.h"
#include "megavox/error.h"
#include "megavox/mvx.h"

namespace {

namespace fmt = mv::mvx_format;

void read_all(const std::string& path) {
  try {
    mv::mvx_content(path);
  } catch (const mv::Error&) {
  }
  try {
    mv::MvxFile file = mv::read_mvx(path);
    MV_FUZZ_CHECK(file.dag.levels >= 1 && file.dag.levels <= 21);
    MV_FUZZ_CHECK(file.grid.resolution == 1u << file.dag.levels);
    if (file.dag.levels <= 5) {  // a validated DAG decodes (small grids only: a DAG of 21 levels can hold 2^63 voxels)
      const std::vector<uint64_t> keys = mv::decode_encoded(file.dag);
      MV_FUZZ_CHECK(std::is_sorted(keys.begin(), keys.end()));
      MV_FUZZ_CHECK(std::adjacent_find(keys.begin(), keys.end()) == keys.end());
      MV_FUZZ_CHECK(keys.empty() || keys.back() < uint64_t{1} << 3 * file.dag.levels);
    }
  } catch (const mv::Error&) {
  }
  try {
    const mv::MvxPages pages(path);
    MV_FUZZ_CHECK(pages.page_words() >= 16 && uint64_t{pages.pages()} * pages.page_words() >= pages.words());
    // A page buffer is the page's size; mutants declaring pages up to 64 MiB would spend the fuzzer's time
    // faulting such buffers in, so their pages are read only where the file holds as many words.
    if (pages.page_words() <= std::max<uint64_t>(pages.words(), 1u << 12)) {
      std::vector<uint32_t> page(pages.page_words());
      std::string error;
      for (uint32_t p = 0; p < std::min<uint32_t>(pages.pages(), 64); ++p) pages.read_page(p, page, &error);
      MV_FUZZ_CHECK(!pages.read_page(pages.pages(), page, &error));
      if (pages.plane_words() != 0) {  // the size plane's pages, as the cache reads them beside the nodes
        std::vector<uint32_t> plane(pages.plane_words());
        for (uint32_t p = 0; p < std::min<uint32_t>(pages.pages(), 64); ++p) pages.read_sizes(p, plane, &error);
        MV_FUZZ_CHECK(!pages.read_sizes(pages.pages(), plane, &error));
      }
    }
    // colour entries (a palette parsed on the first): the first, the last, one past them
    for (uint64_t e : {uint64_t{0}, pages.colour_entries() - 1, pages.colour_entries()}) {
      try {
        pages.colour(e);
        MV_FUZZ_CHECK(e < pages.colour_entries());
      } catch (const mv::Error&) {
      }
    }
  } catch (const mv::Error&) {
  }
  try {
    mv::PointHierarchy h = mv::read_mvx_points(path);
    MV_FUZZ_CHECK(!h.nodes.empty() && h.nodes_per_level.size() == h.depth + 1u);
  } catch (const mv::Error&) {
  }
}

const fmt::Section* section(const fmt::Header& h, uint32_t kind, size_t size) {
  for (uint32_t i = 0; i < std::min(h.sections, fmt::kMaxSections); ++i) {
    const fmt::Section& s = h.table[i];
    if (s.kind == kind && s.offset <= size && s.bytes <= size - s.offset) return &s;
  }
  return nullptr;
}

// The page hashes of an index made right for the words they index (from byte `head_bytes` of the index, pages
// of `page_words` words), where both sections lie in the file.
void fix_hashes(std::vector<uint8_t>& bytes, const fmt::Section* index, const fmt::Section* data, uint64_t head_bytes,
                uint64_t pages, uint64_t page_words) {
  if (!index || !data || index->bytes < head_bytes) return;
  if (page_words < fmt::kMinPageWords || page_words > 2 * uint64_t{fmt::kMaxPageWords}) return;
  const uint64_t words = data->bytes / 4, room = (index->bytes - head_bytes) / 8;
  if (words == 0) return;  // no pages to hash (and memcpy from an empty vector's null data is UB)
  std::vector<uint32_t> stream(words);
  std::memcpy(stream.data(), bytes.data() + data->offset, words * 4);
  for (uint64_t p = 0; p < std::min(pages, room) && p * page_words < words; ++p) {
    const uint64_t hash =
        fmt::page_hash(stream.data() + p * page_words, std::min<uint64_t>(page_words, words - p * page_words), page_words);
    std::memcpy(bytes.data() + index->offset + head_bytes + p * 8, &hash, 8);
  }
}

// Those of the page index over the nodes, and of the size index over the size plane.
void fix_page_hashes(const fmt::Header& h, std::vector<uint8_t>& bytes) {
  const fmt::Section* index = section(h, fmt::kPageIndex, bytes.size());
  if (index && index->bytes >= sizeof(fmt::PageIndexHead)) {
    fmt::PageIndexHead head;
    std::memcpy(&head, bytes.data() + index->offset, sizeof head);
    fix_hashes(bytes, index, section(h, fmt::kNodes, bytes.size()), sizeof head, head.pages, head.page_words);
  }
  const fmt::Section* sizes = section(h, fmt::kSizeIndex, bytes.size());
  if (sizes && sizes->bytes >= sizeof(fmt::SizeIndexHead)) {
    fmt::SizeIndexHead head;
    std::memcpy(&head, bytes.data() + sizes->offset, sizeof head);
    fix_hashes(bytes, sizes, section(h, fmt::kSizes, bytes.size()), sizeof head, head.pages, head.plane_words);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  read_all(mv::fuzz::memory_input(data, size, ".mvx"));
  if (size < sizeof(fmt::Header)) return 0;
  std::vector<uint8_t> fixed(data, data + size);
  fmt::Header h;
  std::memcpy(&h, fixed.data(), sizeof h);
  fix_page_hashes(h, fixed);
  for (uint32_t i = 0; i < std::min(h.sections, fmt::kMaxSections); ++i) {
    fmt::Section& s = h.table[i];
    if (s.offset <= size && s.bytes <= size - s.offset) s.checksum = fmt::hash(fixed.data() + s.offset, s.bytes);
  }
  h.checksum = fmt::hash(&h, offsetof(fmt::Header, checksum));
  if (std::memcmp(&h, fixed.data(), sizeof h) == 0) return 0;  // the checksums were right: read already
  std::memcpy(fixed.data(), &h, sizeof h);
  read_all(mv::fuzz::memory_input(fixed.data(), size, ".mvx"));
  return 0;
}
