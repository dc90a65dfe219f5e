// PLY reader faults: one test per fault, each message checked for its words (one line, naming the file),
// and a deterministic fuzz test: every mutation of a good file must read fine or throw mv::Error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "megavox/error.h"
#include "ply_fixture.h"

namespace {

namespace fs = std::filesystem;
using mv::io::PlyMeshReader;
using namespace mv::test::ply;

// ---------------------------------------------------------------------------------------------------
// Faults

TEST(PlyErrors, MissingFileAndNotAFile) {
  std::string path = temp_file("does_not_exist.ply");
  try {
    PlyMeshReader r(path);
    FAIL() << "no error";
  } catch (const mv::Error& e) {
    EXPECT_EQ(std::string(e.what()), "cannot open '" + path + "': No such file or directory");
  }
  try {
    PlyMeshReader r(fs::path(path).parent_path().string());
    FAIL() << "no error";
  } catch (const mv::Error& e) {
    EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
  }
}

TEST(PlyErrors, NotAPly) {
  expect_error("", {"not a PLY file"});
  expect_error("solid cube\nfacet normal 0 0 1\n", {"not a PLY file"});
  expect_error(std::string(5000, '\x89'), {"not a PLY file"});
  expect_error("ply", {"not a PLY file"});
  expect_error("ply\n", {"header ends at line 2 without 'end_header'"});
}

TEST(PlyErrors, Header) {
  const std::string good = make_ply(small_mesh(), Fmt::ascii);
  expect_error(replace(good, "property float y", "property flaot y"), {"line 6: unknown property type 'flaot'"});
  expect_error(replace(good, "format ascii 1.0", "format ascii 2.0"), {"line 2:", "version '2.0'"});
  expect_error(replace(good, "format ascii", "format binary"), {"line 2:", "unknown format 'binary'"});
  expect_error(replace(good, "format ascii 1.0\n", ""), {"format"});
  expect_error(replace(good.substr(0, header_end(good)), "end_header\n", ""), {"header ends at line 10 without 'end_header'"});
  expect_error(replace(good, "end_header\n", ""), {"line 10: unknown header keyword '0'"});
  expect_error(replace(good, "end_header\n", "end_header junk\n"), {"after 'end_header'"});
  expect_error(replace(good, "element vertex 5", "element vertex -5"), {"line 4:", "element count '-5'"});
  expect_error(replace(good, "element vertex 5", "element vertex 18446744073709551616"), {"element count"});
  expect_error(replace(good, "comment", "remark"), {"line 3: unknown header keyword 'remark'"});
  expect_error(replace(good, "comment made by test_ply\n", "\n"), {"line 3: empty header line"});
  expect_error(replace(good, "element vertex 5\n", "property float w\nelement vertex 5\n"), {"property before any element"});
  expect_error(replace(good, "property float z", "property float z\nproperty float z"), {"duplicate property 'z'"});
  expect_error(replace(good, "end_header", "element vertex 0\nend_header"), {"duplicate element 'vertex'"});
  expect_error(replace(good, "list uchar int", "list float int"), {"count type must be an integer"});
  expect_error(replace(good, "list uchar int", "list uchar float"), {"integer indices"});
  expect_error(replace(good, "vertex_indices", "corners"), {"no list property 'vertex_indices' or 'vertex_index'"});
  expect_error(replace(good, "property float y", "property list uchar float y"), {"vertex property 'y' is a list"});
  expect_error(replace(good, "property float y\n", ""), {"no property 'y'"});
  expect_error(replace(good, "element vertex", "element point"), {"no 'vertex' element"});
  expect_error("ply\nformat binary_little_endian 1.0\nelement face 0\nproperty list uchar int vertex_indices\n"
               "element vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
               {"line 3: element 'face' comes before 'vertex'"});
  // vertex_index is the other common spelling.
  EXPECT_EQ(error_of(replace(good, "vertex_indices", "vertex_index")), "");
}

TEST(PlyErrors, Truncated) {
  MeshSpec m = small_mesh();
  const std::string bin = make_ply(m, Fmt::le);
  const size_t body = header_end(bin);
  // 5 vertices of 12 bytes, then a quad (17 bytes) and 4 triangles (13 bytes each). Too short for the counts
  // at all: found before reading; otherwise found where the data ends.
  expect_error(bin.substr(0, body + 12 * 2 + 5),
               {"truncated: expected 5 vertices, but the 29 bytes after the header hold at most 2"});
  expect_error(bin.substr(0, body + 12 * 5 + 17 + 3), {"truncated: expected 5 faces, file ends after 1"});
  expect_error(bin.substr(0, bin.size() - 1), {"truncated: expected 5 faces, file ends after 4"});
  // Truncated mid-polygon while batching: the triangles already returned do not hide the fault.
  EXPECT_NE(error_of(bin.substr(0, body + 12 * 5 + 9), 1).find("file ends after 0"), std::string::npos);

  const std::string ascii = make_ply(m, Fmt::ascii);
  expect_error(ascii.substr(0, header_end(ascii) + 14), {"truncated: expected 5 vertices", "at most 2"});
  expect_error(ascii.substr(0, ascii.size() - 2), {"truncated: expected 5 faces, file ends after 4"});

  MeshSpec x = m;
  x.extras = true;
  const std::string extra = make_ply(x, Fmt::be);
  expect_error(extra.substr(0, extra.size() - 4), {"truncated: expected 2 'tail' elements, file ends after 1"});
}

TEST(PlyErrors, BadIndices) {
  for (Fmt f : kAllFormats) {
    SCOPED_TRACE(fmt_name(f));
    MeshSpec m = small_mesh();
    m.faces[2][1] = 9999;
    expect_error(make_ply(m, f), {"face 2 refers to vertex 9999 (only 5 vertices)"});
    m.faces[2][1] = -1;
    expect_error(make_ply(m, f), {"face 2 refers to vertex -1 (only 5 vertices)"});
    m.faces[2] = {1, 2};
    expect_error(make_ply(m, f), {"face 2 has 2 vertex indices (a face needs at least 3)"});
    m.faces[2] = {};
    expect_error(make_ply(m, f), {"face 2 has 0 vertex indices"});
  }
  MeshSpec m = small_mesh();
  m.count_type = "int";
  std::string bin = make_ply(m, Fmt::le);
  const int32_t minus3 = -3;
  bin.replace(header_end(bin) + 12 * 5 + 4 + 16, 4, reinterpret_cast<const char*>(&minus3), 4);  // face 1's count
  expect_error(bin, {"face 1: list 'vertex_indices' has negative length -3"});
  expect_error(replace(make_ply(m, Fmt::ascii), "\n3 0 1 4", "\n-3 0 1 4"),
               {"line 17: face 1: list 'vertex_indices' has negative length -3"});
}

TEST(PlyErrors, NonFiniteCoordinates) {
  const double inf = std::numeric_limits<double>::infinity();
  for (Fmt f : kAllFormats) {
    for (double bad : {std::nan(""), inf, -inf, 1e300}) {
      SCOPED_TRACE(std::string(fmt_name(f)) + " " + std::to_string(bad));
      MeshSpec m = small_mesh();
      m.coord_type = "double";
      m.vertices[3][1] = bad;
      expect_error(make_ply(m, f), {"vertex 3: coordinate y = ", "is not a finite float"});
    }
  }
  expect_error(replace(make_ply(small_mesh(), Fmt::ascii), "0.5 0.5 1.25", "0.5 0.5 1e99999"), {"vertex 4: coordinate z"});
}

TEST(PlyErrors, BadAsciiValues) {
  const std::string good = make_ply(small_mesh(), Fmt::ascii);
  expect_error(replace(good, "0.5 0.5 1.25", "0.5 abc 1.25"), {"line 15: 'abc' is not a valid float"});
  expect_error(replace(good, "4 0 1 2 3", "4 0 1 2.5 3"), {"line 16: '2.5' is not a valid int"});
  expect_error(replace(good, "4 0 1 2 3", "256 0 1 2 3"), {"'256' is not a valid uchar"});
  expect_error(replace(good, "0.5 0.5 1.25", "0.5 0.5 " + std::string(100, '1')), {"longer than 64 characters"});
}

TEST(PlyErrors, AbsurdCountsFailBeforeAllocating) {
  const std::string bin = make_ply(small_mesh(), Fmt::le);
  const size_t body = bin.size() - header_end(bin);
  expect_error(replace(bin, "element vertex 5", "element vertex 1000000000000"),
               {"truncated: expected 1000000000000 vertices, but the " + std::to_string(body) +
                " bytes after the header hold at most " + std::to_string(body / 12)});
  expect_error(replace(bin, "element vertex 5", "element vertex 4294967297"), {"expected 4294967297 vertices"});
  expect_error(replace(bin, "element face 5", "element face 18446744073709551615"),
               {"expected 18446744073709551615 faces", "at most " + std::to_string(body - 60)});
  expect_error(replace(make_ply(small_mesh(), Fmt::ascii), "element vertex 5", "element vertex 900000"),
               {"expected 900000 vertices"});
  // An element without properties holds no data, whatever its count.
  EXPECT_EQ(error_of(replace(bin, "end_header", "element nothing 18446744073709551615\nend_header")), "");
}

TEST(PlyErrors, ZeroBatchIsRefused) {
  PlyMeshReader r(write_file("ok.ply", make_ply(small_mesh(), Fmt::le)));
  std::vector<uint32_t> t;
  EXPECT_THROW(r.next_triangles(t, 0), mv::Error);
}

// ---------------------------------------------------------------------------------------------------
// Deterministic fuzzing: every mutation must read fine or throw mv::Error, nothing else.

class Fuzzer {
 public:
  void check(const std::string& bytes, const std::string& what) {
    std::string path = write_file("fuzz.ply", bytes);
    try {
      PlyMeshReader r(path);
      const auto& p = r.positions();
      ASSERT_EQ(p.size(), 3 * r.info().vertices) << what;
      for (float x : p) ASSERT_TRUE(std::isfinite(x)) << what;
      std::vector<uint32_t> t;
      while (r.next_triangles(t, 3))
        for (uint32_t i : t) ASSERT_LT(i, r.info().vertices) << what;
      ++read_;
    } catch (const mv::Error& e) {
      ++failed_;
    } catch (const std::exception& e) {
      ADD_FAILURE() << what << ": not an mv::Error: " << e.what();
    }
  }
  size_t read_ = 0, failed_ = 0;
};

std::vector<std::string> header_lines(const std::string& ply) {
  std::vector<std::string> lines;
  size_t end = header_end(ply), at = 0;
  while (at < end) {
    size_t nl = ply.find('\n', at);
    lines.push_back(ply.substr(at, nl + 1 - at));
    at = nl + 1;
  }
  return lines;
}

TEST(PlyFuzz, MutationsReadOrThrowMvError) {
  MeshSpec m = small_mesh();
  m.extras = true;
  std::mt19937_64 rng(20240601);
  Fuzzer fz;
  for (Fmt f : {Fmt::le, Fmt::ascii, Fmt::be}) {
    const std::string good = make_ply(m, f);
    const std::string name = fmt_name(f);
    fz.check(good, name);
    for (size_t n = 0; n < good.size(); ++n) fz.check(good.substr(0, n), name + " truncated to " + std::to_string(n));
    for (int i = 0; i < 1000; ++i) {
      std::string s = good;
      for (int flips = 1 + static_cast<int>(rng() % 3); flips > 0; --flips) s[rng() % s.size()] = static_cast<char>(rng());
      fz.check(s, name + " flip #" + std::to_string(i));
    }
    auto lines = header_lines(good);
    std::string body = good.substr(header_end(good));
    for (size_t i = 1; i < lines.size(); ++i) {
      for (bool dup : {false, true}) {
        std::string h;
        for (size_t k = 0; k < lines.size(); ++k) h += k != i ? lines[k] : dup ? lines[k] + lines[k] : "";
        fz.check(h + body, name + (dup ? " duplicated line " : " deleted line ") + std::to_string(i));
      }
    }
    for (const char* huge : {"4294967295", "4294967296", "18446744073709551615", "99999999", "6"}) {
      for (const char* el : {"element material 2", "element vertex 5", "element edge 1", "element face 5", "element tail 2"}) {
        std::string s = good;
        std::string from = el, to = from.substr(0, from.rfind(' ') + 1) + huge;
        s.replace(s.find(from), from.size(), to);
        fz.check(s, name + " " + to);
      }
    }
  }
  EXPECT_GT(fz.read_, 0u);
  EXPECT_GT(fz.failed_, 1000u);
}

}  // namespace
