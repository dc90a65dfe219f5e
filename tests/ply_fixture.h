// What the PLY reader tests share: PLY files written in any of the three formats from a mesh description,
// a per-process scratch directory for them, and the checks that read one back or expect a given fault.
#pragma once
#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <string>
#include <vector>

#include "io/ply_reader.h"

namespace mv::test::ply {

enum class Fmt { ascii, le, be };
inline constexpr Fmt kAllFormats[] = {Fmt::ascii, Fmt::le, Fmt::be};

const char* fmt_name(Fmt f);

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

// A path in this process's scratch directory (ctest runs tests in parallel processes), removed at exit.
std::string temp_file(const std::string& name);

// Writes `bytes` to temp_file(name) and returns its path.
std::string write_file(const std::string& name, const std::string& bytes);

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

// A square pyramid: 5 vertices, a quad and 4 triangles.
MeshSpec small_mesh();

// The PLY file of `m` in format `f`.
std::string make_ply(const MeshSpec& m, Fmt f);

// The fan triangulation of `faces`, as the reader returns it.
std::vector<uint32_t> fan(const std::vector<std::vector<double>>& faces);

struct Mesh {
  mv::io::PlyInfo info;
  std::vector<float> positions;
  std::vector<uint32_t> triangles;
};

// Everything in `path`, faces read in batches of `batch` triangles.
Mesh read_all(const std::string& path, size_t batch = 1000, uint64_t ram_bytes = UINT64_MAX);

void expect_mesh(const Mesh& got, const MeshSpec& want);

// The mv::Error message of reading `bytes` completely ("" when it reads fine).
std::string error_of(const std::string& bytes, size_t batch = 1000);

// Reading `bytes` fails with a one-line message that names the file and holds each of `words`.
void expect_error(const std::string& bytes, std::initializer_list<std::string> words);

// `s` with the first `from` replaced by `to` (a failure if there is none).
std::string replace(std::string s, const std::string& from, const std::string& to);

// The offset of the body: just after "end_header\n".
size_t header_end(const std::string& ply);

}  // namespace mv::test::ply
