// PLY reader: round trips in all three formats, batching, one test per fault, a deterministic fuzz test
// and the staged real meshes (when the shared data directory is present).
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "io/ply_reader.h"
#include "megavox/error.h"

#ifndef MEGAVOX_SOURCE_DIR
#define MEGAVOX_SOURCE_DIR "."
#endif

namespace {

namespace fs = std::filesystem;
using mv::io::PlyMeshReader;

enum class Fmt { ascii, le, be };
const Fmt kAllFormats[] = {Fmt::ascii, Fmt::le, Fmt::be};

const char* fmt_name(Fmt f) {
  return f == Fmt::ascii ? "ascii" : f == Fmt::le ? "binary_little_endian" : "binary_big_endian";
}

// One directory per test process (ctest runs tests in parallel processes), removed at exit.
struct TempDir {
  fs::path dir = fs::temp_directory_path() / ("megavox_test_ply_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(dir); }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

std::string temp_file(const std::string& name) {
  static TempDir temp;
  return (temp.dir / name).string();
}

std::string write_file(const std::string& name, const std::string& bytes) {
  std::string path = temp_file(name);
  // Unlinked first: ext4 flushes a file truncated and rewritten on close, which made the fuzz test I/O bound.
  std::error_code ec;
  fs::remove(path, ec);
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path;
}

// Appends values of a PLY body in one format.
class BodyWriter {
 public:
  explicit BodyWriter(Fmt f) : fmt_(f) {}

  void put(const std::string& type, double v) {
    if (fmt_ == Fmt::ascii) {
      char text[40];
      bool integer = type != "float" && type != "double" && type != "float32" && type != "float64";
      std::snprintf(text, sizeof text, integer ? "%.0f " : "%.17g ", v);
      out_ += text;
    } else if (type == "char" || type == "int8") {
      put_bytes(static_cast<int8_t>(v));
    } else if (type == "uchar" || type == "uint8") {
      put_bytes(static_cast<uint8_t>(v));
    } else if (type == "short" || type == "int16") {
      put_bytes(static_cast<int16_t>(v));
    } else if (type == "ushort" || type == "uint16") {
      put_bytes(static_cast<uint16_t>(v));
    } else if (type == "int" || type == "int32") {
      put_bytes(static_cast<int32_t>(v));
    } else if (type == "uint" || type == "uint32") {
      put_bytes(static_cast<uint32_t>(v));
    } else if (type == "float" || type == "float32") {
      put_bytes(static_cast<float>(v));
    } else {
      put_bytes(v);
    }
  }
  void end_entry() {
    if (fmt_ == Fmt::ascii) out_.back() = '\n';
  }
  const std::string& bytes() const { return out_; }

 private:
  template <class T>
  void put_bytes(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if ((fmt_ == Fmt::be) == (std::endian::native == std::endian::little)) std::reverse(b, b + sizeof(T));
    out_.append(b, sizeof(T));
  }

  Fmt fmt_;
  std::string out_;
};

struct MeshSpec {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::vector<double>> faces;  // double so tests can write negative and out-of-range indices
  std::string coord_type = "float";
  std::string count_type = "uchar";
  std::string index_type = "int";
  // Colours and a normal between the coordinates, a face property on each side of the index list, and
  // skipped elements with list properties before the vertices, between vertices and faces, and after faces.
  bool extras = false;
  bool vertex_list = false;  // a list property in the vertex element (not a fixed-size record)
  bool with_faces = true;
};

MeshSpec small_mesh() {
  MeshSpec m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1.25}};
  m.faces = {{0, 1, 2, 3}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  return m;
}

std::string make_ply(const MeshSpec& m, Fmt f) {
  const std::string& c = m.coord_type;
  std::string h = "ply\nformat " + std::string(fmt_name(f)) + " 1.0\ncomment made by test_ply\n";
  BodyWriter w(f);
  if (m.extras) {
    h += "element material 2\nproperty uchar id\nproperty list uint8 float32 weights\n";
    for (int i = 0; i < 2; ++i) {
      w.put("uchar", i);
      w.put("uint8", 2);
      w.put("float32", 0.25);
      w.put("float32", 0.75);
      w.end_entry();
    }
  }
  h += "element vertex " + std::to_string(m.vertices.size()) + "\n";
  h += m.extras ? "property " + c + " x\nproperty uchar red\nproperty " + c + " y\nproperty uchar green\nproperty " + c +
                      " z\nproperty uchar blue\nproperty float nx\n"
                : "property " + c + " x\nproperty " + c + " y\nproperty " + c + " z\n";
  if (m.vertex_list) h += "property list ushort uint neighbours\n";
  for (const auto& v : m.vertices) {
    for (int k = 0; k < 3; ++k) {
      w.put(c, v[k]);
      if (m.extras) w.put("uchar", 200 + k);
    }
    if (m.extras) w.put("float", -1.5);
    if (m.vertex_list) {
      w.put("ushort", 2);
      w.put("uint", 1);
      w.put("uint", 2);
    }
    w.end_entry();
  }
  if (m.extras) {
    h += "element edge 1\nproperty list int int16 ends\n";
    w.put("int", 3);
    for (int k = 0; k < 3; ++k) w.put("int16", -k);
    w.end_entry();
  }
  if (m.with_faces) {
    h += "element face " + std::to_string(m.faces.size()) + "\n";
    if (m.extras) h += "property uchar flags\n";
    h += "property list " + m.count_type + " " + m.index_type + " vertex_indices\n";
    if (m.extras) h += "property list uchar float texcoord\n";
    for (const auto& face : m.faces) {
      if (m.extras) w.put("uchar", 7);
      w.put(m.count_type, static_cast<double>(face.size()));
      for (double i : face) w.put(m.index_type, i);
      if (m.extras) {
        w.put("uchar", 2);
        w.put("float", 0.5);
        w.put("float", 0.25);
      }
      w.end_entry();
    }
  }
  if (m.extras) {
    h += "element tail 2\nproperty list int uint tags\nproperty double w\n";
    for (int i = 0; i < 2; ++i) {
      w.put("int", i);
      if (i) w.put("uint", 4000000000.0);
      w.put("double", 1.0 / 3);
      w.end_entry();
    }
  }
  return h + "end_header\n" + w.bytes();
}

std::vector<uint32_t> fan(const std::vector<std::vector<double>>& faces) {
  std::vector<uint32_t> t;
  for (const auto& f : faces)
    for (size_t k = 2; k < f.size(); ++k)
      t.insert(t.end(), {static_cast<uint32_t>(f[0]), static_cast<uint32_t>(f[k - 1]), static_cast<uint32_t>(f[k])});
  return t;
}

struct Mesh {
  mv::io::PlyInfo info;
  std::vector<float> positions;
  std::vector<uint32_t> triangles;
};

Mesh read_all(const std::string& path, size_t batch = 1000, uint64_t ram_bytes = UINT64_MAX) {
  PlyMeshReader r(path, ram_bytes);
  EXPECT_EQ(r.positions_mapped(), r.info().vertices * 12 > ram_bytes);
  Mesh m{r.info(), {r.positions().begin(), r.positions().end()}, {}};
  std::vector<uint32_t> part;
  while (r.next_triangles(part, batch)) m.triangles.insert(m.triangles.end(), part.begin(), part.end());
  EXPECT_TRUE(part.empty());
  return m;
}

void expect_mesh(const Mesh& got, const MeshSpec& want) {
  ASSERT_EQ(got.info.vertices, want.vertices.size());
  ASSERT_EQ(got.positions.size(), 3 * want.vertices.size());
  for (size_t i = 0; i < want.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(got.positions[3 * i + k], static_cast<float>(want.vertices[i][k]));
  EXPECT_EQ(got.info.faces, want.with_faces ? want.faces.size() : 0);
  EXPECT_EQ(got.triangles, want.with_faces ? fan(want.faces) : std::vector<uint32_t>{});
}

// The mv::Error message of reading `bytes` completely ("" when it reads fine).
std::string error_of(const std::string& bytes, size_t batch = 1000) {
  std::string path = write_file("bad.ply", bytes);
  try {
    read_all(path, batch);
  } catch (const mv::Error& e) {
    return e.what();
  }
  return "";
}

void expect_error(const std::string& bytes, std::initializer_list<std::string> words) {
  std::string msg = error_of(bytes);
  ASSERT_FALSE(msg.empty()) << "no error";
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  EXPECT_NE(msg.find("bad.ply: "), std::string::npos) << msg;
  for (const auto& w : words) EXPECT_NE(msg.find(w), std::string::npos) << "'" << w << "' not in: " << msg;
}

std::string replace(std::string s, const std::string& from, const std::string& to) {
  size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

size_t header_end(const std::string& ply) { return ply.find("end_header\n") + 11; }

// ---------------------------------------------------------------------------------------------------

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

// ---------------------------------------------------------------------------------------------------
// Staged real meshes, counts from shared/data/README.md.

TEST(PlySharedData, StagedMeshesMatchTheReadme) {
  const char* env = std::getenv("MEGAVOX_TEST_DATA");
  fs::path root = env && *env ? fs::path(env) : fs::path(MEGAVOX_SOURCE_DIR) / ".." / "shared" / "data";
  if (!fs::is_directory(root)) {
    std::printf("shared data not found at %s: skipping shared-data checks\n", root.string().c_str());
    return;
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
