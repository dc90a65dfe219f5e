// open_mesh (host/formats/io/mesh_source.h) on a file named .obj: assimp's OBJ importer (a PLY by content goes to
// megavox's own reader instead), then every triangle. A crash inside assimp is third-party: see
// BENCHMARKS.md, "Fuzzing".
#include <cmath>
#include <vector>

#include "fuzz_support.h"
#include "throwing_new.h"  // its large blocks kept: assimp's OBJ importer fills two 16 MiB buffers per file
#include "io/mesh_source.h"
#include "megavox/error.h"

// Leaks of blocks allocated inside libassimp are third-party, not findings: assimp's OBJ importer leaks what it
// had built when it gives up on a file (BENCHMARKS.md, "Fuzzing"; the input is in fuzz/known/).
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so\n"; }

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = mv::fuzz::memory_input(data, size, ".obj");
  const size_t batch = 1 + size % 61;
  try {
    auto mesh = mv::io::open_mesh(path);
    const uint64_t vertices = mesh->positions().size() / 3;
    MV_FUZZ_CHECK(mesh->positions().size() % 3 == 0);
    for (float c : mesh->positions()) MV_FUZZ_CHECK(std::isfinite(c));
    std::vector<uint32_t> triangles;
    while (mesh->next_triangles(triangles, batch)) {
      MV_FUZZ_CHECK(!triangles.empty() && triangles.size() % 3 == 0 && triangles.size() <= 3 * batch);
      for (uint32_t i : triangles) MV_FUZZ_CHECK(i < vertices);
    }
  } catch (const mv::Error&) {
  }
  return 0;
}
