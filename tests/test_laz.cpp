// megavox's LAZ decoder (host/formats/laz) on PDAL's LAZ test files (../shared/data/pointcloud_laz):
// - every record equals the uncompressed twin's, where PDAL has one (pointwise v1 and v2, LASzip and libLAS);
// - every record equals laz-perf's decode (LASzip in WebAssembly, tests/js/laz_decode.mjs), where node and the
//   pinned package are installed;
// - the reader's columns equal the twin's whatever the threads and the batch size;
// - damaged files (cut short, a chunk table that lies, an unknown compressor or item, a point count that lies,
//   items that do not make the point format, flipped bytes) each fail with an mv::Error naming the file, and
//   points convert leaves nothing behind.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "io/las_convert.h"
#include "io/point_source.h"
#include "megavox/error.h"
#include "ply_fixture.h"
#include "point_fixture.h"
#include "test_support.h"

namespace {

namespace fs = std::filesystem;
using mv::test::shared_data_file;
using mv::test::ply::temp_file;
using mv::test::ply::write_file;

std::string laz_file(const std::string& name) { return shared_data_file("pointcloud_laz/" + name); }

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

template <class T>
T le_at(const std::string& b, size_t at) {
  T v;
  std::memcpy(&v, b.data() + at, sizeof v);
  return v;
}

template <class T>
std::string patched(std::string bytes, size_t at, T v) {
  std::memcpy(bytes.data() + at, &v, sizeof v);
  return bytes;
}

// The point records of a plain LAS file's bytes.
std::string records_of(const std::string& las) {
  const uint32_t offset = le_at<uint32_t>(las, 96);
  const uint16_t length = le_at<uint16_t>(las, 105);
  uint64_t count = le_at<uint32_t>(las, 107);
  if (las[25] >= 4 && count == 0) count = le_at<uint64_t>(las, 247);
  return las.substr(offset, count * length);
}

// The records megavox decodes from `laz`, through points convert's library call.
std::string decoded_records(const std::string& laz, unsigned threads = 0) {
  const std::string out = temp_file("decoded.las");
  mv::io::write_plain_las(laz, out, threads);
  return records_of(file_bytes(out));
}

// Where the LASzip record's payload starts in a LAZ file's bytes.
size_t laszip_record(const std::string& b) {
  size_t at = le_at<uint16_t>(b, 94);
  for (uint32_t k = 0; k < le_at<uint32_t>(b, 100); ++k) {
    if (std::memcmp(b.data() + at + 2, "laszip encoded", 14) == 0) return at + 54;
    at += 54 + le_at<uint16_t>(b, at + 20);
  }
  return 0;
}

struct Twin {
  const char* laz;
  const char* las;
};
constexpr Twin kTwins[] = {
    {"pointcloud_laz/simple.laz", "pointcloud_laz/simple.las"},
    {"pointcloud_laz/liblas-generated.laz", "pointcloud_laz/simple.las"},
    {"pointcloud_laz/simple-laszip-compressor-version-1.2r0.laz", "pointcloud_laz/simple.las"},
    {"pointcloud_laz/autzen_trim.laz", "pointcloud_autzen/autzen_trim.las"},
};

TEST(Laz, EveryRecordEqualsTheUncompressedTwin) {
  MV_SKIP_WITHOUT_SHARED_DATA("pointcloud_laz/simple.laz");
  for (const Twin& t : kTwins) {
    const std::string laz = shared_data_file(t.laz), las = shared_data_file(t.las);
    if (las.empty()) continue;
    const std::string want = records_of(file_bytes(las));
    EXPECT_EQ(decoded_records(laz), want) << t.laz;
    EXPECT_EQ(decoded_records(laz, 1), want) << t.laz << " on one thread";
  }
}

TEST(Laz, ConvertKeepsTheHeaderAndRecordsAndDropsLaszips) {
  MV_SKIP_WITHOUT_SHARED_DATA("pointcloud_laz/autzen_trim.laz");
  const std::string laz = laz_file("autzen_trim.laz"), out = temp_file("autzen_plain.las");
  const mv::io::LasConvertReport r = mv::io::write_plain_las(laz, out, 0);
  EXPECT_EQ(r.points, 110000u);
  EXPECT_NE(r.input_format.find("LAZ 1.2, point format 3 (LASzip 2.2, pointwise chunked, 3 chunks)"),
            std::string::npos)
      << r.input_format;
  const std::string in = file_bytes(laz), plain = file_bytes(out);
  EXPECT_EQ(static_cast<uint8_t>(plain[104]), 3);
  EXPECT_EQ(laszip_record(plain), 0u);
  EXPECT_EQ(le_at<uint32_t>(plain, 100), le_at<uint32_t>(in, 100) - 1);
  EXPECT_EQ(plain.substr(131, 227 - 131), in.substr(131, 227 - 131));  // scale, offset, bounds
  EXPECT_EQ(plain.size(), le_at<uint32_t>(plain, 96) + 110000ull * 34);
  // The plain file reads as the LAZ does.
  const auto a = mv::test::points::read_cloud(laz), b = mv::test::points::read_cloud(out);
  EXPECT_EQ(a.points.xyz, b.points.xyz);
  EXPECT_EQ(a.points.rgb, b.points.rgb);
  EXPECT_EQ(a.info.crs, b.info.crs);
}

TEST(Laz, ColumnsDoNotDependOnThreadsOrBatches) {
  MV_SKIP_WITHOUT_SHARED_DATA("pointcloud_laz/las_with_several_extra_byte_bloc.laz");
  const std::string laz = laz_file("las_with_several_extra_byte_bloc.laz");
  mv::io::PointReadOptions one;
  one.threads = 1;
  mv::io::PointReadOptions small;
  small.ram_bytes = 4096;  // a batch of one chunk at a time
  const auto a = mv::test::points::read_cloud(laz, 1 << 20, one);
  const auto b = mv::test::points::read_cloud(laz, 977, small);
  EXPECT_EQ(a.info.points, 697721u);
  EXPECT_EQ(a.points.xyz, b.points.xyz);
  EXPECT_EQ(a.points.rgb, b.points.rgb);
  EXPECT_EQ(a.points.intensity, b.points.intensity);
  EXPECT_EQ(a.points.extra, b.points.extra);
  // The LAS fields (with format 8's GPS time and NIR), then the extra bytes two Extra Bytes records type.
  EXPECT_EQ(a.info.extra_bytes, 24u + 3u);
  ASSERT_EQ(a.info.fields.size(), 14u);
  EXPECT_EQ(a.info.fields[12].name, "Deviation");
  EXPECT_EQ(a.info.fields[12].type, mv::PointFieldType::u16);
  EXPECT_EQ(a.info.fields[12].offset, 24u);
  EXPECT_EQ(a.info.fields[13].name, "confidence");
  EXPECT_EQ(a.info.fields[13].offset, 26u);
  EXPECT_NE(a.info.format.find("LAZ 1.4, point format 8"), std::string::npos) << a.info.format;
}

// skip(n) passes over whole chunks unread and decodes the rest of a chunk it ends in: the points after it are
// the whole read's (a build over ranks reads its slice so).
TEST(Laz, SkipPassesOverWholeChunksUnread) {
  MV_SKIP_WITHOUT_SHARED_DATA("pointcloud_laz/autzen_trim.laz");
  const std::string laz = laz_file("autzen_trim.laz");
  const auto whole = mv::test::points::read_cloud(laz);
  const uint64_t n = whole.info.points;
  for (uint64_t k : {uint64_t{0}, uint64_t{50000}, uint64_t{50001}, n - 1, n, n + 10}) {
    auto src = mv::io::open_points(laz);
    const uint64_t unread = src->skip(k);
    EXPECT_EQ(unread, k >= n ? n : k / 50000 * 50000) << k;  // its chunks hold 50,000 points (the last fewer)
    mv::PointColumns rest;
    while (src->next(rest, 4096)) {}
    const uint64_t from = std::min(k, n);
    ASSERT_EQ(rest.size(), n - from) << k;
    EXPECT_TRUE(std::equal(rest.xyz.begin(), rest.xyz.end(), whole.points.xyz.begin() + 3 * from)) << k;
    EXPECT_TRUE(std::equal(rest.extra.begin(), rest.extra.end(), whole.points.extra.begin() + whole.info.extra_bytes * from)) << k;
  }
}

// laz-perf in node: the independent decoder of every staged LAZ file it reads (it has no version-1 items).
TEST(Laz, EveryRecordEqualsLazPerfs) {
  MV_SKIP_WITHOUT_SHARED_DATA("pointcloud_laz/simple.laz");
  const std::string js = std::string(MEGAVOX_SOURCE_DIR) + "/tests/js";
  if (!fs::exists(js + "/node_modules/laz-perf") || std::system("command -v node >/dev/null 2>&1") != 0) {
    std::printf("Laz.EveryRecordEqualsLazPerfs: not run: no node or tests/js/node_modules/laz-perf "
                "(scripts/setup.sh installs them)\n");
    return;
  }
  for (const char* name : {"simple.laz", "liblas-generated.laz", "autzen_trim.laz", "1.2-with-color.copc.laz",
                           "las_with_several_extra_byte_bloc.laz"}) {
    const std::string laz = laz_file(name), theirs = temp_file("lazperf.bin");
    const std::string command = "node '" + js + "/laz_decode.mjs' '" + laz + "' '" + theirs + "' >/dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0) << command;
    EXPECT_EQ(decoded_records(laz), file_bytes(theirs)) << name;
  }
}

// ---------------------------------------------------------------------------------------------------
// Bounded reads

// The records of `plain` (a plain LAS file's bytes) whose world position lies in `box`.
std::string records_inside(const std::string& plain, const std::array<double, 6>& box) {
  const std::string all = records_of(plain);
  const size_t length = le_at<uint16_t>(plain, 105);
  std::string out;
  for (size_t at = 0; at < all.size(); at += length) {
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      const double w = le_at<double>(plain, 155 + 8 * a) + le_at<double>(plain, 131 + 8 * a) * le_at<int32_t>(all, at + 4 * a);
      inside = inside && w >= box[a] && w <= box[3 + a];
    }
    if (inside) out += all.substr(at, length);
  }
  return out;
}

// A box over part of a file's header bounds: fractions `lo` to `hi` of each axis.
std::array<double, 6> part_of(const std::string& file, double lo, double hi) {
  const std::string b = file_bytes(file);
  std::array<double, 6> box{};
  for (int a = 0; a < 3; ++a) {
    const double mx = le_at<double>(b, 179 + 16 * a), mn = le_at<double>(b, 187 + 16 * a);
    box[a] = mn + lo * (mx - mn);
    box[3 + a] = mn + hi * (mx - mn);
  }
  box[2] = -1e30, box[5] = 1e30;  // every height
  return box;
}

// COPC decodes only the chunks whose node meets the box, and keeps exactly the points a filter of the whole
// cloud keeps; other LAS and LAZ files read everything and keep the same.
TEST(Laz, BoundedReadsEqualFilteringTheWholeCloud) {
  MV_SKIP_WITHOUT_SHARED_DATA("pointcloud_laz/1.2-with-color.copc.laz");
  for (const char* name : {"1.2-with-color.copc.laz", "autzen_trim.laz", "simple.las"}) {
    const std::string in = laz_file(name);
    const std::string whole = temp_file("whole.las"), part = temp_file("part.las");
    const mv::io::LasConvertReport all = mv::io::write_plain_las(in, whole, 0);
    for (const auto& [lo, hi] : {std::pair{0.0, 0.3}, std::pair{0.4, 0.6}, std::pair{0.0, 1.0}, std::pair{2.0, 3.0}}) {
      const std::array<double, 6> box = part_of(in, lo, hi);
      const mv::io::LasConvertReport r = mv::io::write_plain_las(in, part, 0, {}, box);
      const std::string want = records_inside(file_bytes(whole), box), plain = file_bytes(part);
      EXPECT_EQ(records_of(plain), want) << name << " " << lo << "-" << hi;
      EXPECT_EQ(r.points_written * r.record_length, want.size());
      const bool v14 = plain[25] >= 4;
      EXPECT_EQ(v14 ? le_at<uint64_t>(plain, 247) : le_at<uint32_t>(plain, 107), r.points_written);
      if (std::string(name).find("copc") != std::string::npos && hi - lo < 0.5) {
        EXPECT_LT(r.chunks_read, all.chunks_read) << name << ": the box should skip chunks";
      }
      // The point reader keeps the same points.
      mv::io::PointReadOptions o;
      o.bounds = box;
      auto src = mv::io::open_points(in, o);
      mv::PointColumns cols;
      while (src->next(cols, 1000)) {
      }
      EXPECT_EQ(cols.size(), r.points_written) << name;
      EXPECT_GE(src->info().points, cols.size());
    }
    EXPECT_EQ(laszip_record(file_bytes(whole)), 0u);
  }
}

// ---------------------------------------------------------------------------------------------------
// Damaged files

// Converting `bytes` (as file `name`) fails with an mv::Error naming the file and holding `words`, and
// leaves no output.
void expect_convert_fault(const std::string& name, const std::string& bytes, const std::string& words) {
  const std::string in = write_file(name, bytes), out = temp_file("fault_out.las");
  fs::remove(out);
  const std::string message = mv::test::error_message([&] { mv::io::write_plain_las(in, out, 0); });
  EXPECT_NE(message.find(in), std::string::npos) << message;
  EXPECT_NE(message.find(words), std::string::npos) << "'" << words << "' not in: " << message;
  EXPECT_FALSE(fs::exists(out)) << name;
  // The point reader says the same.
  const std::string read = mv::test::points::read_error(name, bytes);
  EXPECT_NE(read.find(words), std::string::npos) << "'" << words << "' not in: " << read;
}

TEST(LazErrors, EachDamageIsNamed) {
  MV_SKIP_WITHOUT_SHARED_DATA("pointcloud_laz/autzen_trim.laz");
  const std::string good = file_bytes(laz_file("autzen_trim.laz"));
  const size_t vlr = laszip_record(good);
  ASSERT_NE(vlr, 0u);
  const uint32_t points_at = le_at<uint32_t>(good, 96);
  const int64_t table = le_at<int64_t>(good, points_at);

  expect_convert_fault("cut_in_chunks.laz", good.substr(0, good.size() / 2), "chunk table position");
  expect_convert_fault("cut_table.laz", good.substr(0, table + 9), "chunk table");
  expect_convert_fault("table_far.laz", patched<int64_t>(good, points_at, int64_t{1} << 40), "chunk table position");
  expect_convert_fault("table_version.laz", patched<uint32_t>(good, table, 7), "chunk table version 7");
  expect_convert_fault("table_chunks.laz", patched<uint32_t>(good, table + 4, 9), "lists 9 chunks");
  expect_convert_fault("compressor.laz", patched<uint16_t>(good, vlr, 7), "unknown LAZ compressor 7");
  expect_convert_fault("coder.laz", patched<uint16_t>(good, vlr + 2, 1), "unknown LAZ coder 1");
  expect_convert_fault("item_type.laz", patched<uint16_t>(good, vlr + 34, 10), "do not make point format 3");
  expect_convert_fault("item_version.laz", patched<uint16_t>(good, vlr + 34 + 4, 9), "version 9 is not read");
  expect_convert_fault("item_size.laz", patched<uint16_t>(good, vlr + 34 + 2, 21), "make records of 35 bytes");
  expect_convert_fault("more_points.laz", patched<uint32_t>(good, 107, 110001), "end before its 10001 points do");
  expect_convert_fault("fewer_points.laz", patched<uint32_t>(good, 107, 50000), "make 1");
  expect_convert_fault("no_record.laz", patched<char>(good, vlr - 54 + 2, 'X'), "no LASzip record");
  // The second chunk's bytes cut short: the table's sizes lie about the data.
  std::string shifted = good;
  shifted.erase(points_at + 8 + 1000, 5000);
  expect_convert_fault("chunk_short.laz", patched<int64_t>(shifted, points_at, table - 5000), "corrupt LAZ");
}

// Flipped bytes in the compressed points: each file decodes (to other points) or fails with an mv::Error;
// nothing crashes or reads out of bounds (the sanitizer build checks the latter).
TEST(LazErrors, FlippedBytesDecodeOrFailCleanly) {
  MV_SKIP_WITHOUT_SHARED_DATA("pointcloud_laz/1.2-with-color.copc.laz");
  for (const char* name : {"simple.laz", "simple-laszip-compressor-version-1.2r0.laz", "1.2-with-color.copc.laz"}) {
    const std::string good = file_bytes(laz_file(name));
    const uint32_t points_at = le_at<uint32_t>(good, 96);
    std::mt19937 rng(17);
    for (int trial = 0; trial < 40; ++trial) {
      std::string bad = good;
      for (int f = 0; f < 1 + trial % 4; ++f) {
        const size_t at = points_at + 8 + rng() % (good.size() - points_at - 8);
        bad[at] = static_cast<char>(bad[at] ^ (1 + rng() % 255));
      }
      (void)mv::test::points::read_error("flipped.laz", bad);
    }
  }
}

}  // namespace
