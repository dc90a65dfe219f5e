// The .mvx readers (include/megavox/mvx.h): read_mvx and read_mvx_points on the same bytes.
//
// Every section and the header carry an XXH3 checksum, which random mutations almost never keep right; so
// each input is read twice: as it is (the checksum checks), and with its checksums recomputed over what its
// section table points at (what lies behind them: the sizes, the counts, the encoding's validation).
#include <algorithm>
#include <cstddef>
#include <cstring>
#include <vector>

#include "fuzz_support.h"
#include "io/mvx_format.h"
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
    mv::PointHierarchy h = mv::read_mvx_points(path);
    MV_FUZZ_CHECK(!h.nodes.empty() && h.nodes_per_level.size() == h.depth + 1u);
  } catch (const mv::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  read_all(mv::fuzz::write_input(data, size, ".mvx"));
  if (size < sizeof(fmt::Header)) return 0;
  std::vector<uint8_t> fixed(data, data + size);
  fmt::Header h;
  std::memcpy(&h, fixed.data(), sizeof h);
  for (uint32_t i = 0; i < std::min(h.sections, fmt::kMaxSections); ++i) {
    fmt::Section& s = h.table[i];
    if (s.offset <= size && s.bytes <= size - s.offset) s.checksum = fmt::hash(fixed.data() + s.offset, s.bytes);
  }
  h.checksum = fmt::hash(&h, offsetof(fmt::Header, checksum));
  if (std::memcmp(&h, fixed.data(), sizeof h) == 0) return 0;  // the checksums were right: read already
  std::memcpy(fixed.data(), &h, sizeof h);
  read_all(mv::fuzz::write_input(fixed.data(), size, ".mvx"));
  return 0;
}
