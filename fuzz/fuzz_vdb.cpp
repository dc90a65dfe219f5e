// read_vdb (host/formats/io/vdb_source.h): an OpenVDB file's first grid as voxels, at its own size or resampled. A
// crash inside OpenVDB is third-party: see BENCHMARKS.md, "Fuzzing".
#include <algorithm>
#include <vector>

#include "fuzz_support.h"
// OpenVDB allocates sizes read from the file: over 64 MiB is a bad_alloc. Large blocks are not kept for reuse
// here: in fork mode that bought no executions (about 430/s against 412/s over 120 s), while OpenVDB's leaked
// nodes, held in power-of-two blocks, took jobs to their 2 GiB limit, where clang 14's heap profile then hung
// them (BENCHMARKS.md, "Fuzzing").
#define MV_REUSE_LARGE_BLOCKS 0
#include "throwing_new.h"
#include "io/vdb_source.h"
#include "megavox/error.h"

// Leaks of blocks allocated inside libopenvdb are third-party, not findings: OpenVDB's Archive::readGrid leaks
// the tree node it was reading when reading it throws (BENCHMARKS.md, "Fuzzing"; the input is in fuzz/known/).
extern "C" const char* __lsan_default_suppressions() { return "leak:libopenvdb.so\n"; }

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = mv::fuzz::memory_input(data, size, ".vdb");
  // Odd sizes resample to 4 voxels per axis, even ones keep one VDB voxel per voxel.
  const uint32_t resolution = size % 2 ? 4 : 0;
  try {
    mv::io::VdbVoxels v = mv::io::read_vdb(path, "", resolution);
    MV_FUZZ_CHECK(!v.keys.empty() && std::is_sorted(v.keys.begin(), v.keys.end()));
    MV_FUZZ_CHECK(std::adjacent_find(v.keys.begin(), v.keys.end()) == v.keys.end());
    const uint32_t r = v.grid.resolution;
    // A power of two up to 2^21 (64-bit Morton keys), and every key inside the grid.
    MV_FUZZ_CHECK(r >= 1 && r <= (1u << 21) && (r & (r - 1)) == 0 && (resolution == 0 || r == resolution));
    MV_FUZZ_CHECK(v.keys.back() < uint64_t{r} * r * r);
  } catch (const mv::Error&) {
  }
  return 0;
}
