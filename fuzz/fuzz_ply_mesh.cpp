// PlyMeshReader (host/formats/io/ply_reader.h): the header, every vertex and every triangle; and opened with its
// vertices deferred, a range of them read by offset.
#include <algorithm>
#include <cmath>
#include <vector>

#include "fuzz_support.h"
#include "io/ply_reader.h"
#include "megavox/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = mv::fuzz::memory_input(data, size, ".ply");
  // The input's size picks the reader's options, so that one corpus covers them all: odd sizes put the
  // vertex positions in the mapped scratch file (a RAM budget of 0), and batches are 1 to 61 triangles (a
  // polygon may be split between batches).
  const uint64_t ram_bytes = size % 2 ? 0 : UINT64_MAX;
  const size_t batch = 1 + size % 61;
  try {
    mv::io::PlyMeshReader reader(path, ram_bytes);
    const uint64_t vertices = reader.info().vertices;
    MV_FUZZ_CHECK(reader.positions().size() == 3 * vertices);
    for (float c : reader.positions()) MV_FUZZ_CHECK(std::isfinite(c));
    std::vector<uint32_t> triangles;
    uint64_t total = 0;
    while (reader.next_triangles(triangles, batch)) {
      MV_FUZZ_CHECK(!triangles.empty() && triangles.size() % 3 == 0 && triangles.size() <= 3 * batch);
      for (uint32_t i : triangles) MV_FUZZ_CHECK(i < vertices);
      total += triangles.size() / 3;
    }
    MV_FUZZ_CHECK(triangles.empty());
    MV_FUZZ_CHECK(total >= reader.info().faces);  // every polygon gives at least one triangle
  } catch (const mv::Error&) {
  }
  // Opened for a build over ranks: the vertices deferred, then a range of them read by offset, each checked.
  try {
    mv::io::PlyMeshReader reader(path, ram_bytes, true);
    const uint64_t vertices = reader.info().vertices;
    if (reader.vertices_deferred()) {
      MV_FUZZ_CHECK(reader.positions().empty());
      const uint64_t first = vertices / 3, last = std::min<uint64_t>(vertices, first + 1 + size % 97);
      std::vector<float> xyz;
      std::vector<uint16_t> rgb;
      reader.read_vertex_range(first, last, xyz, rgb);
      MV_FUZZ_CHECK(xyz.size() == 3 * (last - first));
      for (float c : xyz) MV_FUZZ_CHECK(std::isfinite(c));
    }
  } catch (const mv::Error&) {
  }
  return 0;
}
