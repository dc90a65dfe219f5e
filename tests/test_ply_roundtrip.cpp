// PLY reader: well-formed files read back exactly -- round trips in all three formats and every scalar
// type, fan triangulation, batching, a file larger than the reader's buffer -- and the staged real meshes
// (skipped when the shared data directory is absent).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "ply_fixture.h"

#ifndef MEGAVOX_SOURCE_DIR
#define MEGAVOX_SOURCE_DIR "."
#endif

namespace {

namespace fs = std::filesystem;
using mv::io::PlyMeshReader;
using namespace mv::test::ply;

TEST(Ply, RoundTripAllFormats) {
  for (Fmt f : kAllFormats) {
    SCOPED_TRACE(fmt_name(f));
    MeshSpec m = small_mesh();
    std::string path = write_file("rt.ply", make_ply(m, f));
    Mesh got = read_all(path);
    expect_mesh(got, m);
    EXPECT_EQ(got.info.format, fmt_name(f));
    EXPECT_EQ(got.info.comments, std::vector<std::string>{"made by test_ply"});
  }
}

TEST(Ply, RoundTripDoublesExtraPropertiesAndElements) {
  for (Fmt f : kAllFormats) {
    for (const char* coord : {"double", "float64", "short", "int8"}) {
      SCOPED_TRACE(std::string(fmt_name(f)) + " " + coord);
      MeshSpec m = small_mesh();
      m.extras = true;
      m.vertex_list = coord[0] == 'i' || coord[0] == 'd';  // half the cases leave the binary fast path
      m.coord_type = coord;
      if (m.coord_type == "double" || m.coord_type == "float64") m.vertices[4] = {0.1, -1e-30, 123456.789};
      else m.vertices[4] = {2, -1, -3};  // integers only
      expect_mesh(read_all(write_file("rt.ply", make_ply(m, f))), m);
      expect_mesh(read_all(write_file("rt.ply", make_ply(m, f)), 1000, 0), m);  // positions in a scratch file
    }
  }
}

TEST(Ply, RoundTripIndexTypes) {
  const char* types[][2] = {{"uchar", "int"}, {"int", "int"}, {"uint8", "uint32"}, {"ushort", "short"},
                            {"int32", "uchar"}, {"char", "ushort"}, {"uint", "uint"}};
  for (Fmt f : kAllFormats) {
    for (auto [count, index] : types) {
      SCOPED_TRACE(std::string(fmt_name(f)) + " list " + count + " " + index);
      MeshSpec m = small_mesh();
      m.count_type = count;
      m.index_type = index;
      m.faces.push_back({0, 1, 2, 3, 4, 0, 2});  // a heptagon: 5 fan triangles
      expect_mesh(read_all(write_file("rt.ply", make_ply(m, f))), m);
    }
  }
}

TEST(Ply, QuadsAreFanTriangulated) {
  MeshSpec m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 2, 2}};
  m.faces = {{0, 1, 2, 3}, {4, 3, 2, 1, 0}};
  Mesh got = read_all(write_file("quad.ply", make_ply(m, Fmt::le)));
  EXPECT_EQ(got.triangles, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3, 4, 3, 2, 4, 2, 1, 4, 1, 0}));
}

TEST(Ply, PointCloudWithoutFacesIsAnEmptyMesh) {
  for (Fmt f : kAllFormats) {
    MeshSpec m = small_mesh();
    m.with_faces = false;
    m.extras = true;
    expect_mesh(read_all(write_file("points.ply", make_ply(m, f))), m);
  }
}

TEST(Ply, EmptyFaceElement) {
  MeshSpec m = small_mesh();
  m.faces.clear();
  expect_mesh(read_all(write_file("noface.ply", make_ply(m, Fmt::ascii))), m);
}

// Batches of 1, 2 and 1000 triangles, on the generic face walker (extras) and the binary fast path.
TEST(Ply, Batching) {
  for (Fmt f : kAllFormats) {
    for (bool extras : {false, true}) {
      MeshSpec m = small_mesh();
      m.extras = extras;
      m.faces.push_back({4, 3, 2, 1, 0});  // 3 triangles: split across batches of 2
      m.faces.push_back({0, 1, 2});
      const std::vector<uint32_t> want = fan(m.faces);
      std::string path = write_file("batch.ply", make_ply(m, f));
      for (size_t batch : {1, 2, 1000}) {
        SCOPED_TRACE(std::string(fmt_name(f)) + (extras ? " extras" : "") + " batch " + std::to_string(batch));
        PlyMeshReader r(path);
        std::vector<uint32_t> all, part;
        size_t calls = 0;
        while (r.next_triangles(part, batch)) {
          ++calls;
          ASSERT_LE(part.size(), 3 * batch);
          if (all.size() + part.size() < want.size()) {
            EXPECT_EQ(part.size(), 3 * batch);  // only the last batch may be short
          }
          all.insert(all.end(), part.begin(), part.end());
        }
        EXPECT_EQ(all, want);
        EXPECT_EQ(calls, (want.size() / 3 + batch - 1) / batch);
        EXPECT_FALSE(r.next_triangles(part, batch));  // stays at the end
        EXPECT_TRUE(part.empty());
      }
    }
  }
}

// A file larger than the reader's 1 MiB buffer: records and polygons straddle refills.
TEST(Ply, LargerThanTheBuffer) {
  MeshSpec m;
  for (int i = 0; i < 40000; ++i) m.vertices.push_back({i * 0.5, -i * 0.25, static_cast<double>(i % 7)});
  for (int i = 0; i < 70000; ++i) {
    std::vector<double> face;
    for (int k = 0; k < 3 + i % 4; ++k) face.push_back((i * 31 + k * 977) % 40000);
    m.faces.push_back(face);
  }
  for (Fmt f : {Fmt::le, Fmt::be}) {
    std::string path = write_file("large.ply", make_ply(m, f));
    ASSERT_GT(fs::file_size(path), 1u << 20);
    for (size_t batch : {7, 100000}) {
      SCOPED_TRACE(std::string(fmt_name(f)) + " batch " + std::to_string(batch));
      expect_mesh(read_all(path, batch), m);
    }
  }
}

// ---------------------------------------------------------------------------------------------------
// Staged real meshes, counts from shared/data/README.md.

// select_faces: a share of a binary file's triangles read by offset is that slice of the whole read; it refuses
// ascii files and faces with other properties, and a face that is not a triangle fails as it is read.
TEST(Ply, SelectFacesReadsAShareByOffset) {
  MeshSpec m;
  for (int i = 0; i < 40; ++i) m.vertices.push_back({double(i), double(i % 7), double(i % 3)});
  for (int f = 0; f < 300; ++f) m.faces.push_back({double(f % 40), double((f * 7 + 1) % 40), double((f * 13 + 2) % 40)});
  for (Fmt f : {Fmt::le, Fmt::be}) {
    for (const std::string index_type : {"int", "ushort"}) {
      m.index_type = index_type;
      const std::string path = write_file("share.ply", make_ply(m, f));
      const std::vector<uint32_t> all = read_all(path).triangles;
      for (auto [first, last] : {std::pair<uint64_t, uint64_t>{0, 300}, {0, 1}, {17, 150}, {299, 300}, {120, 120}}) {
        PlyMeshReader r(path);
        ASSERT_TRUE(r.select_faces(first, last)) << fmt_name(f);
        std::vector<uint32_t> got, batch;
        while (r.next_triangles(batch, 7)) got.insert(got.end(), batch.begin(), batch.end());
        EXPECT_EQ(got, std::vector<uint32_t>(all.begin() + 3 * first, all.begin() + 3 * last)) << first << " " << last;
        EXPECT_EQ(r.bytes_spanned() < std::filesystem::file_size(path), last - first < 300);
      }
    }
  }
  m.index_type = "int";
  PlyMeshReader ascii(write_file("share_ascii.ply", make_ply(m, Fmt::ascii)));
  EXPECT_FALSE(ascii.select_faces(0, 10));
  EXPECT_EQ(ascii.bytes_spanned(), std::filesystem::file_size(temp_file("share_ascii.ply")));
  MeshSpec quad = m;
  quad.faces[5] = {1, 2, 3, 4};
  PlyMeshReader r(write_file("share_quad.ply", make_ply(quad, Fmt::le)));
  ASSERT_TRUE(r.select_faces(0, 300));
  std::vector<uint32_t> batch;
  EXPECT_NE(mv::test::error_message([&] { while (r.next_triangles(batch, 100)) {} }).find("needs triangles"),
            std::string::npos);
  MeshSpec extras = m;
  extras.extras = true;
  PlyMeshReader e(write_file("share_extras.ply", make_ply(extras, Fmt::le)));
  EXPECT_FALSE(e.select_faces(0, 10));
}

// A build over ranks reads the vertices in shares: opened deferred, a binary file reads none, then any range by
// offset gives the positions of a whole read; an ascii file reads them all as usual.
TEST(Ply, DeferredVerticesReadARangeByOffset) {
  MeshSpec m;
  for (int i = 0; i < 40; ++i) m.vertices.push_back({double(i) * 0.5, double(i % 7), -double(i % 3)});
  for (int f = 0; f < 30; ++f) m.faces.push_back({double(f % 40), double((f * 7 + 1) % 40), double((f * 13 + 2) % 40)});
  for (Fmt f : {Fmt::le, Fmt::be}) {
    const std::string path = write_file("deferred.ply", make_ply(m, f));
    const PlyMeshReader whole(path);
    PlyMeshReader r(path, UINT64_MAX, true);
    ASSERT_TRUE(r.vertices_deferred()) << fmt_name(f);
    EXPECT_TRUE(r.positions().empty());
    for (auto [first, last] : {std::pair<uint64_t, uint64_t>{0, 40}, {3, 17}, {39, 40}, {12, 12}}) {
      std::vector<float> xyz;
      std::vector<uint16_t> rgb;
      r.read_vertex_range(first, last, xyz, rgb);
      EXPECT_TRUE(std::equal(xyz.begin(), xyz.end(), whole.positions().begin() + 3 * first)) << first;
      EXPECT_EQ(xyz.size(), 3 * (last - first));
    }
    ASSERT_TRUE(r.select_faces(10, 20));  // the faces are where they are without the vertices read
    std::vector<uint32_t> got, batch;
    while (r.next_triangles(batch, 4)) got.insert(got.end(), batch.begin(), batch.end());
    const std::vector<uint32_t> all = read_all(path).triangles;
    EXPECT_EQ(got, std::vector<uint32_t>(all.begin() + 30, all.begin() + 60));
    std::vector<float> xyz;
    std::vector<uint16_t> rgb;
    EXPECT_NE(mv::test::error_message([&] { r.read_vertex_range(30, 41, xyz, rgb); }).find("not a range"),
              std::string::npos);
  }
  PlyMeshReader ascii(write_file("deferred_ascii.ply", make_ply(m, Fmt::ascii)), UINT64_MAX, true);
  EXPECT_FALSE(ascii.vertices_deferred());
  EXPECT_EQ(ascii.positions().size(), 120u);
}

TEST(PlySharedData, StagedMeshesMatchTheReadme) {
  const char* env = std::getenv("MEGAVOX_TEST_DATA");
  fs::path root = env && *env ? fs::path(env) : fs::path(MEGAVOX_SOURCE_DIR) / ".." / "shared" / "data";
  if (!fs::is_directory(root)) {
    GTEST_SKIP() << "shared data not found at " << root.string() << " (set MEGAVOX_TEST_DATA)";
  }
  struct Staged {
    const char* file;
    uint64_t vertices, triangles;
  };
  const Staged staged[] = {{"meshes_stanford/bunny_npm_small.ply", 1839, 3674},
                           {"meshes_stanford/stanford_bunny.ply", 35947, 69451},
                           {"meshes_misc/spot.ply", 2930, 5856},
                           {"pointcloud_autzen/autzen_trim.ply", 110000, 0}};
  for (const Staged& s : staged) {
    SCOPED_TRACE(s.file);
    Mesh m = read_all((root / s.file).string(), 4096);
    EXPECT_EQ(m.info.format, "binary_little_endian");
    EXPECT_EQ(m.info.vertices, s.vertices);
    EXPECT_EQ(m.info.faces, s.triangles);
    EXPECT_EQ(m.triangles.size(), 3 * s.triangles);
    EXPECT_FALSE(m.info.comments.empty());  // each staged file names its source
    for (uint32_t i : m.triangles) ASSERT_LT(i, s.vertices);
  }
}

}  // namespace
