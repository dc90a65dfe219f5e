// Point-cloud reader faults: one test per kind, each message checked for its words (naming the file), and a
// deterministic fuzz test: every mutation of a good LAS or PLY file must read fine or throw mv::Error.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "io/las_reader.h"
#include "io/point_source.h"
#include "megavox/error.h"
#include "point_fixture.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using namespace mv::test::points;
using mv::test::ply::Fmt;
using mv::test::ply::temp_file;
using mv::test::ply::write_file;

// Reading `bytes` (as file `name`) fails with a one-line message naming the file and holding each of `words`.
void expect_fault(const std::string& name, const std::string& bytes, std::initializer_list<std::string> words) {
  const std::string message = read_error(name, bytes);
  ASSERT_NE(message, "") << "no error for " << name;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_NE(message.find(temp_file(name)), std::string::npos) << message;
  for (const std::string& w : words)
    EXPECT_NE(message.find(w), std::string::npos) << "'" << w << "' not in: " << message;
}

template <class T>
std::string patched(std::string bytes, size_t at, T v) {
  std::memcpy(bytes.data() + at, &v, sizeof v);  // LAS is little-endian, as the test hosts are
  return bytes;
}

std::string good_las(int minor = 2, int format = 3, size_t n = 37) {
  LasSpec spec;
  spec.minor = minor;
  spec.format = format;
  spec.wkt = "PROJCS[\"x\"]";
  return make_las(spec, las_points(n, 0, 5));
}

// ---------------------------------------------------------------------------------------------------
// Any file

TEST(PointReadErrors, MissingFileAndUnknownContent) {
  const std::string missing = temp_file("does_not_exist.las");
  EXPECT_EQ(mv::test::error_message([&] { mv::io::open_points(missing); }),
            "cannot open '" + missing + "': No such file or directory");
  for (const std::string& bytes : {std::string(), std::string("hello"), std::string("LAS"), std::string("PLY\n")})
    expect_fault("unknown.xyz", bytes, {"not a point cloud megavox reads", "PLY", "LAS", "'ply'", "'LASF'"});
  const std::string dir = fs::path(missing).parent_path().string();
  EXPECT_NE(mv::test::error_message([&] { mv::io::open_las(dir, {}); }), "");
}

// ---------------------------------------------------------------------------------------------------
// LAS

TEST(LasErrors, WrongSignatureAndTruncatedHeader) {
  const std::string good = good_las();
  const std::string path = write_file("sig.las", "LASX" + good.substr(4));
  EXPECT_NE(mv::test::error_message([&] { mv::io::open_las(path, {}); }).find("not a LAS file"), std::string::npos);
  expect_fault("sig2.las", "LASX" + good.substr(4), {"not a point cloud"});
  expect_fault("short.las", good.substr(0, 100), {"truncated LAS header", "the file has 100 bytes", "at least 227"});
  expect_fault("short14.las", good_las(4, 6).substr(0, 300), {"truncated LAS header", "LAS 1.4 header needs 375"});
  expect_fault("short13.las", good_las(3, 1).substr(0, 230), {"LAS 1.3 header needs 235"});
}

TEST(LasErrors, TruncatedPoints) {
  const std::string good = good_las();  // 37 points of 34 bytes
  expect_fault("cut.las", good.substr(0, good.size() - 10),
               {"truncated point data", "declares 37 points of 34 bytes", "ends after 36 complete points"});
  expect_fault("cut0.las", good.substr(0, good.size() - 37 * 34 + 5), {"ends after 0 complete points"});

  // Cut after opening: the stream finds it.
  const std::string large = good_las(2, 3, 5000);
  const std::string path = write_file("cut_later.las", large);
  auto src = mv::io::open_points(path);
  fs::resize_file(path, large.size() - 34 * 4971 - 3);
  mv::PointColumns cols;
  const std::string message = mv::test::error_message([&] {
    while (src->next(cols, 3)) {
    }
  });
  EXPECT_NE(message.find(path + ": truncated point data: the header declares 5000 points, but the file ends after 28 "
                                "complete points"),
            std::string::npos)
      << message;
}

TEST(LasErrors, CountsLargerThanTheFile) {
  const std::string good = good_las();
  expect_fault("count.las", patched<uint32_t>(good, 107, 4000000000u),
               {"declares 4000000000 points", "ends after 37 complete points"});
  const std::string good14 = good_las(4, 7);
  expect_fault("count14.las", patched<uint64_t>(good14, 247, uint64_t{1} << 62),
               {"declares 4611686018427387904 points"});
  expect_fault("legacy14.las", patched<uint32_t>(good_las(4, 1), 107, 36),
               {"legacy point count 36 disagrees with the 64-bit count 37"});
  expect_fault("vlrs.las", patched<uint32_t>(good, 100, 1000000), {"1000000 variable-length records cannot fit"});
  expect_fault("vlrlen.las", patched<uint16_t>(good, 227 + 20, 60000),
               {"variable-length record 0", "runs past the start of the point data"});
}

TEST(LasErrors, BadHeaderFields) {
  const std::string good = good_las();
  expect_fault("hsize.las", patched<uint16_t>(good, 94, 100), {"bad LAS header", "100 bytes", "at least 227"});
  expect_fault("offset.las", patched<uint32_t>(good, 96, 200),
               {"point data starts at byte 200, inside the 227-byte header"});
  expect_fault("offset2.las", patched<uint32_t>(good, 96, 1u << 30),
               {"truncated LAS file", "should start at byte 1073741824"});
  expect_fault("scale.las", patched<double>(good, 139, 0.0), {"Y scale factor", "not a finite non-zero number"});
  expect_fault("scalenan.las", patched<double>(good, 131, std::numeric_limits<double>::quiet_NaN()),
               {"X scale factor"});
  expect_fault("offinf.las", patched<double>(good, 171, std::numeric_limits<double>::infinity()),
               {"Z offset is not finite"});
  expect_fault("reclen.las", patched<uint16_t>(good, 105, 30),
               {"records of 30 bytes are shorter than the 34 bytes of point format 3"});
  expect_fault("version.las", patched<uint8_t>(good, 25, 5), {"LAS 1.5 is not supported (LAS 1.0 to 1.4 are read)"});
  expect_fault("version2.las", patched<uint8_t>(good, 24, 2), {"LAS 2.2 is not supported"});
  LasSpec evlr;
  evlr.minor = 4;
  evlr.format = 6;
  evlr.wkt = "X";
  evlr.wkt_in_evlr = true;
  const std::string e = make_las(evlr, las_points(4, 0, 1));
  expect_fault("evlr.las", patched<uint64_t>(e, 235, 400), {"extended variable-length records start at byte 400"});
  expect_fault("evlrlen.las", patched<uint64_t>(e, e.size() - 60 - 2 + 20, 1000),
               {"extended variable-length record 0", "runs past the end"});
}

TEST(LasErrors, UnsupportedPointFormats) {
  for (int format : {11, 63})
    expect_fault("fmt.las", patched<uint8_t>(good_las(), 104, static_cast<uint8_t>(format)),
                 {"point data record format " + std::to_string(format) + " is not supported", "formats 0 to 10 are read"});
}

TEST(LasErrors, CompressedWithoutItsLaszipRecord) {
  const std::string good = good_las();
  const std::string want = "the point format says LAZ (compressed), but the file has no LASzip record";
  expect_fault("bit7.las", patched<uint8_t>(good, 104, 0x83), {want});
  expect_fault("bit6.las", patched<uint8_t>(good, 104, 0x43), {want});
  // The content decides, not the name.
  expect_fault("NAMED.LAZ", "\x01\x02 not LAS at all", {"not a point cloud megavox reads"});
  EXPECT_EQ(read_error("named.laz", good), "");
}

// ---------------------------------------------------------------------------------------------------
// PLY

std::vector<PlyColumn> xyz_columns(size_t n) {
  std::vector<PlyColumn> cols = {{"float", "x", {}}, {"float", "y", {}}, {"float", "z", {}}};
  for (size_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a) cols[a].values.push_back(0.5 * i - a);
  return cols;
}

TEST(PlyPointErrors, NonFiniteCoordinates) {
  auto cols = xyz_columns(10);
  cols[1].values[3] = std::numeric_limits<double>::quiet_NaN();
  expect_fault("nan.ply", make_cloud_ply(Fmt::le, cols), {"vertex 3: coordinate y = nan is not finite"});
  expect_fault("nan_be.ply", make_cloud_ply(Fmt::be, cols), {"vertex 3: coordinate y = nan is not finite"});
  cols = xyz_columns(10);
  cols[2].values[7] = -std::numeric_limits<double>::infinity();
  expect_fault("inf.ply", make_cloud_ply(Fmt::ascii, cols), {"line 16: vertex 7: coordinate z = -inf is not finite"});
  cols = xyz_columns(10);
  cols[0].values[9] = 1e300;  // beyond float: infinite as a float
  expect_fault("big.ply", make_cloud_ply(Fmt::ascii, cols), {"vertex 9: coordinate x = inf is not finite"});
}

TEST(PlyPointErrors, LayoutAndTruncation) {
  const std::string good = make_cloud_ply(Fmt::le, xyz_columns(10));
  expect_fault("novertex.ply", mv::test::ply::replace(good, "element vertex", "element point"),
               {"no 'vertex' element"});
  expect_fault("noz.ply", mv::test::ply::replace(good, "property float z", "property float w"),
               {"line 4:", "no property 'z'"});
  expect_fault("list.ply", mv::test::ply::replace(good, "property float y", "property list uchar float y"),
               {"vertex property 'y' is a list"});
  expect_fault("cut.ply", good.substr(0, good.size() - 5), {"truncated", "10 vertices", "at most 9"});
  expect_fault("count.ply", mv::test::ply::replace(good, "element vertex 10", "element vertex 1000000000000"),
               {"truncated: expected 1000000000000 vertices"});
  expect_fault("cut_ascii.ply", make_cloud_ply(Fmt::ascii, xyz_columns(10)).substr(0, 150), {"truncated"});
  expect_fault("header.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1\n", {"without 'end_header'"});

  // A list in the vertex element takes the generic walker, which finds the cut when it reaches it.
  std::string lists =
      mv::test::ply::replace(good, "property float z\n", "property float z\nproperty list uchar int n\n");
  lists = lists.substr(0, mv::test::ply::header_end(lists));
  for (int i = 0; i < 10; ++i) {
    const float v[3] = {1, 2, 3};
    lists.append(reinterpret_cast<const char*>(v), 12);
    lists += i == 9 ? std::string("\x05", 1) : std::string(1, '\0');
  }
  expect_fault("cut_list.ply", lists, {"truncated: expected 10 vertices, file ends after 9"});
}

// ---------------------------------------------------------------------------------------------------
// Fuzz: flipped, overwritten and cut bytes

// Reads every mutation of `good`; returns how many read fine (the rest threw mv::Error, checked by read_error).
size_t fuzz(const std::string& name, const std::string& good, size_t header_bytes, int variants, uint64_t seed) {
  std::mt19937_64 rng(seed);
  size_t fine = 0;
  for (int v = 0; v < variants; ++v) {
    std::string bytes = good;
    const int op = static_cast<int>(rng() % 4);
    // Most mutations hit the header, where a byte decides more than one value.
    const size_t span = rng() % 4 == 0 ? bytes.size() : std::min(header_bytes, bytes.size());
    if (op == 3) {
      bytes.resize(rng() % bytes.size());
    } else {
      const int n = 1 + static_cast<int>(rng() % 3);
      for (int k = 0; k < n; ++k) {
        char& c = bytes[rng() % span];
        c = op == 0   ? static_cast<char>(c ^ (1 << (rng() % 8)))
            : op == 1 ? static_cast<char>(rng())
                      : static_cast<char>(c + 1);
      }
    }
    SCOPED_TRACE("variant " + std::to_string(v));
    if (read_error(name, bytes, 1 + rng() % 16).empty()) ++fine;
    if (::testing::Test::HasFailure()) break;  // one report is enough
  }
  return fine;
}

TEST(PointReadFuzz, LasMutations) {
  LasSpec a;
  a.minor = 4;
  a.format = 8;
  a.extra_bytes = 2;
  a.wkt = "PROJCS[\"fuzz\"]";
  a.geokey_crs = 2992;
  LasSpec b;
  b.minor = 4;
  b.format = 7;
  b.wkt = "GEOGCS[\"fuzz\"]";
  b.wkt_in_evlr = true;
  LasSpec c;  // LAS 1.2, format 3
  c.geokey_crs = 4326;
  size_t fine = 0, total = 0;
  uint64_t seed = 25;
  for (const LasSpec& s : {a, b, c}) {
    const std::string good = make_las(s, las_points(12, s.extra_bytes, seed));
    fine += fuzz("fuzz.las", good, 600, 1000, ++seed);
    total += 1000;
  }
  std::printf("%zu of %zu LAS mutations read fine, the rest threw mv::Error\n", fine, total);
  EXPECT_GT(fine, 0u);
  EXPECT_LT(fine, total);
}

TEST(PointReadFuzz, PlyMutations) {
  std::vector<PlyColumn> cols = xyz_columns(12);
  for (const char* name : {"red", "green", "blue"}) cols.push_back({"uchar", name, std::vector<double>(12, 100)});
  for (const char* name : {"nx", "ny", "nz"}) cols.push_back({"float", name, std::vector<double>(12, 0.5)});
  cols.push_back({"ushort", "intensity", std::vector<double>(12, 700)});
  size_t fine = 0, total = 0;
  uint64_t seed = 52;
  for (Fmt f : mv::test::ply::kAllFormats) {
    const std::string good = make_cloud_ply(f, cols, true);
    fine += fuzz("fuzz.ply", good, mv::test::ply::header_end(good), 1000, ++seed);
    total += 1000;
  }
  std::printf("%zu of %zu PLY mutations read fine, the rest threw mv::Error\n", fine, total);
  EXPECT_GT(fine, 0u);
  EXPECT_LT(fine, total);
}

}  // namespace
