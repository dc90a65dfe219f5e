// read_symvox (host/formats/io/symvox_file.h): SymVox-family DAG files. There is no magic number and no format
// argument: the reader tells the 32-bit layout (.svdag, .ussvdag) from the 16-bit one (.ssvdag) by the sizes
// the content declares, so one target covers both (seeds of each in fuzz/corpus/fuzz_symvox/).
#include <algorithm>
#include <vector>

#include "fuzz_support.h"
#include "io/symvox_file.h"
#include "megavox/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = mv::fuzz::write_input(data, size, ".svdag");
  try {
    mv::io::SymvoxFile f = mv::io::read_symvox(path);
    MV_FUZZ_CHECK(f.file_bytes == size && f.levels >= 1 && f.levels <= 21 && f.dag.levels == f.levels);
    const bool words = f.dag.encoding == mv::Encoding::svdag || f.dag.encoding == mv::Encoding::ussvdag;
    MV_FUZZ_CHECK(words || f.dag.encoding == mv::Encoding::ssvdag);
    if (f.levels <= 5) {  // a validated DAG decodes (small grids only: 21 levels can hold 2^63 voxels)
      const std::vector<uint64_t> keys = mv::decode_encoded(f.dag);
      MV_FUZZ_CHECK(std::is_sorted(keys.begin(), keys.end()));
      MV_FUZZ_CHECK(std::adjacent_find(keys.begin(), keys.end()) == keys.end());
      MV_FUZZ_CHECK(keys.empty() || keys.back() < uint64_t{1} << 3 * f.levels);
    }
  } catch (const mv::Error&) {
  }
  return 0;
}
