// The PLY test fixture (declarations and what each helper does in ply_fixture.h): a body writer for each
// format, the mesh-to-PLY writer, and reading a file back or catching its fault.
#include "ply_fixture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "megavox/error.h"
#include "test_support.h"

namespace mv::test::ply {

namespace {

namespace fs = std::filesystem;
using mv::io::PlyMeshReader;

}  // namespace

const char* fmt_name(Fmt f) {
  return f == Fmt::ascii ? "ascii" : f == Fmt::le ? "binary_little_endian" : "binary_big_endian";
}

std::string temp_file(const std::string& name) { return temp_path("ply_" + name); }

std::string write_file(const std::string& name, const std::string& bytes) {
  std::string path = temp_file(name);
  // Unlinked first: ext4 flushes a file truncated and rewritten on close, which made the fuzz test I/O bound.
  std::error_code ec;
  fs::remove(path, ec);
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return path;
}

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

Mesh read_all(const std::string& path, size_t batch, uint64_t ram_bytes) {
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

std::string error_of(const std::string& bytes, size_t batch) {
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

}  // namespace mv::test::ply
