// Point-cloud readers: LAS files of every version and point format written here and read back field by field,
// PLY clouds in the three formats with their attributes and the grid rule, and the staged real clouds (the
// autzen LAS against its PLY copy, point by point).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "io/ply_points.h"
#include "io/point_source.h"
#include "megavox/error.h"
#include "point_fixture.h"
#include "test_support.h"

namespace {

using namespace mv::test::points;
using mv::PointColumns;
using mv::io::PlyGrid;
using mv::io::PointReadOptions;
using mv::test::ply::Fmt;
using mv::test::ply::fmt_name;
using mv::test::ply::kAllFormats;
using mv::test::ply::write_file;

bool has_rgb(int format) { return format == 2 || format == 3 || format == 5 || format == 7 || format == 8 || format == 10; }

// ---------------------------------------------------------------------------------------------------
// PointColumns

TEST(PointReaders, ColumnsAppendAndClear) {
  PointColumns from;
  from.xyz = {1, 2, 3, 4, 5, 6};
  from.rgb = {10, 11, 12, 13, 14, 15};
  from.intensity = {7, 8};
  from.extra = {1, 2, 3, 4};
  PointColumns to;
  to.append(from, 1, 2);
  to.append(from, 0, 2);
  EXPECT_EQ(to.size(), 2u);
  EXPECT_EQ(to.xyz, (std::vector<int32_t>{4, 5, 6, 1, 2, 3}));
  EXPECT_EQ(to.rgb, (std::vector<uint16_t>{13, 14, 15, 10, 11, 12}));
  EXPECT_TRUE(to.normal.empty());
  EXPECT_EQ(to.intensity, (std::vector<uint16_t>{8, 7}));
  EXPECT_EQ(to.extra, (std::vector<uint8_t>{3, 4, 1, 2}));
  to.clear();
  EXPECT_EQ(to.size(), 0u);
  EXPECT_TRUE(to.rgb.empty() && to.intensity.empty() && to.extra.empty());
}

// ---------------------------------------------------------------------------------------------------
// LAS

TEST(LasPoints, EveryVersionFormatAndExtraBytes) {
  for (int minor : {0, 1, 2, 3, 4}) {  // 1.0 and 1.1 share 1.2's layout
    for (int format : {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10}) {
      for (uint16_t extra : {0, 3}) {
        for (bool carry : {true, false}) {
          SCOPED_TRACE("LAS 1." + std::to_string(minor) + " format " + std::to_string(format) + " extra " +
                       std::to_string(extra) + (carry ? " carried" : " skipped"));
          LasSpec spec;
          spec.minor = minor;
          spec.format = format;
          spec.extra_bytes = extra;
          spec.wkt = "PROJCS[\"NAD83(HARN) / Oregon GIC Lambert (ft)\"]";
          const auto pts = las_points(37, extra, 1000 * minor + 10 * format + extra);
          const std::string path = write_file("roundtrip.las", make_las(spec, pts));
          PointReadOptions options;
          options.carry_extra_bytes = carry;
          const Cloud c = read_cloud(path, 5, options);

          const mv::PointCloudInfo& info = c.info;
          EXPECT_EQ(info.format, "LAS 1." + std::to_string(minor) + ", point format " + std::to_string(format));
          EXPECT_EQ(info.points, 37u);
          EXPECT_EQ(c.batches, 8u);
          EXPECT_TRUE(info.z_up);
          EXPECT_EQ(info.crs, spec.wkt);
          EXPECT_EQ(info.attributes, mv::kPointIntensity | (has_rgb(format) ? mv::kPointRgb : 0u) |
                                         (carry ? mv::kPointExtra : 0u));
          // The attribute record: the decoded LAS fields, then the extra bytes (unnamed: no Extra Bytes record).
          const bool gps = format == 1 || format >= 3;
          const bool wave = format == 4 || format == 5 || format == 9 || format == 10;
          const uint32_t standard = 14 + (gps ? 8 : 0) + (format == 8 || format == 10 ? 2 : 0) + (wave ? 29 : 0);
          EXPECT_EQ(info.extra_bytes, carry ? standard + extra : 0u);
          const mv::PointField* cls = nullptr;
          const mv::PointField* gps_time = nullptr;
          const mv::PointField* nir = nullptr;
          const mv::PointField* unnamed = nullptr;
          const mv::PointField* wave_offset = nullptr;
          for (const mv::PointField& f : info.fields) {
            if (f.name == "classification") cls = &f;
            if (f.name == "gps_time") gps_time = &f;
            if (f.name == "nir") nir = &f;
            if (f.name == "extra_bytes") unnamed = &f;
            if (f.name == "wave_packet_offset") wave_offset = &f;
          }
          if (carry) {
            ASSERT_TRUE(cls);
            EXPECT_EQ(gps_time != nullptr, gps);
            EXPECT_EQ(nir != nullptr, format == 8 || format == 10);
            EXPECT_EQ(wave_offset != nullptr, wave);
            ASSERT_EQ(unnamed != nullptr, extra > 0);
            if (unnamed) {
              EXPECT_EQ(unnamed->offset, standard);
              EXPECT_EQ(unnamed->count, extra);
            }
          } else {
            EXPECT_TRUE(info.fields.empty());
          }
          for (int a = 0; a < 3; ++a) {
            EXPECT_EQ(info.scale[a], spec.scale[a]);
            EXPECT_EQ(info.offset[a], spec.offset[a]);
          }
          const PointColumns& p = c.points;
          ASSERT_EQ(p.size(), pts.size());
          EXPECT_TRUE(p.normal.empty());
          EXPECT_EQ(p.rgb.size(), has_rgb(format) ? 3 * pts.size() : 0u);
          EXPECT_EQ(p.extra.size(), carry ? info.extra_bytes * pts.size() : 0u);
          for (size_t i = 0; i < pts.size(); ++i) {
            for (int a = 0; a < 3; ++a) ASSERT_EQ(p.xyz[3 * i + a], pts[i].xyz[a]) << "point " << i;
            ASSERT_EQ(p.intensity[i], pts[i].intensity) << "point " << i;
            if (has_rgb(format)) {
              for (int k = 0; k < 3; ++k) ASSERT_EQ(p.rgb[3 * i + k], pts[i].rgb[k]) << "point " << i;
            }
            if (carry) {
              const uint8_t* rec = &p.extra[info.extra_bytes * i];
              ASSERT_EQ(rec[cls->offset], format >= 6 ? pts[i].classification : pts[i].classification & 31);
              if (gps) {
                double t;
                std::memcpy(&t, rec + gps_time->offset, 8);
                ASSERT_EQ(t, pts[i].gps_time) << "point " << i;
              }
              if (nir) ASSERT_EQ(rec[nir->offset] | rec[nir->offset + 1] << 8, pts[i].nir);
              if (wave) {  // the fixture fills the descriptor with 'w'
                ASSERT_EQ(wave_offset->type, mv::PointFieldType::u64);
                ASSERT_EQ(rec[wave_offset->offset - 1], 'w');
                ASSERT_EQ(rec[wave_offset->offset + 27], 'w');
              }
              for (int k = 0; k < extra; ++k) ASSERT_EQ(rec[standard + k], pts[i].extra[k]) << "point " << i;
            }
          }
        }
      }
    }
  }
}

TEST(LasPoints, WorldIsOffsetPlusScaleTimesX) {
  LasSpec spec;
  std::vector<LasPoint> pts(1);
  pts[0].xyz[0] = 117798;
  pts[0].xyz[1] = -5;
  pts[0].xyz[2] = 3;
  const Cloud c = read_cloud(write_file("world.las", make_las(spec, pts)));
  const double want[3] = {636000.5 + 1177.98, -20 - 0.005, 3 + 0.75};
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(c.info.offset[a] + c.info.scale[a] * c.points.xyz[a], want[a], 1e-9);
}

TEST(LasPoints, CrsFromWktOrGeoKeys) {
  auto crs = [](const LasSpec& spec) {
    return read_cloud(write_file("crs.las", make_las(spec, las_points(3, 0, 1)))).info.crs;
  };
  LasSpec none;
  EXPECT_EQ(crs(none), "");
  LasSpec keys;
  keys.geokey_crs = 2992;
  EXPECT_EQ(crs(keys), "GeoTIFF keys (EPSG:2992)");
  keys.geokey_crs = 32767;
  EXPECT_EQ(crs(keys), "GeoTIFF keys (user-defined CRS)");
  LasSpec both = keys;
  both.wkt = "GEOGCS[\"WGS 84\"]";
  EXPECT_EQ(crs(both), both.wkt);  // the WKT wins over the keys
  LasSpec evlr;
  evlr.minor = 4;
  evlr.format = 7;
  evlr.wkt = "PROJCS[\"in an EVLR\"]";
  evlr.wkt_in_evlr = true;
  EXPECT_EQ(crs(evlr), evlr.wkt);
}

TEST(LasPoints, GapBeforePointsTinyBufferAndEmptyCloud) {
  LasSpec spec;
  spec.gap = 13;
  spec.extra_bytes = 1;
  const auto pts = las_points(50, 1, 9);
  const std::string path = write_file("gap.las", make_las(spec, pts));
  PointReadOptions one_record;
  one_record.ram_bytes = 1;  // a buffer of one record
  const Cloud c = read_cloud(path, 1000, one_record);
  ASSERT_EQ(c.points.size(), 50u);
  for (size_t i = 0; i < pts.size(); ++i) ASSERT_EQ(c.points.xyz[3 * i + 2], pts[i].xyz[2]);
  EXPECT_EQ(c.points.extra[c.info.extra_bytes * 50 - 1], pts[49].extra[0]);  // the record's last byte

  const Cloud empty = read_cloud(write_file("empty.las", make_las(spec, {})));
  EXPECT_EQ(empty.info.points, 0u);
  EXPECT_EQ(empty.batches, 0u);

  auto src = mv::io::open_points(path);
  PointColumns cols;
  EXPECT_NE(mv::test::error_message([&] { src->next(cols, 0); }).find("max_points must be at least 1"),
            std::string::npos);
}

// skip(n) passes over n points as next() would: an uncompressed LAS seeks (the next points are the same), a PLY
// reader reads them; past the end it stops there. LAZ's chunks: test_laz.cpp.
TEST(PointReaders, SkipPassesOverPoints) {
  LasSpec spec;
  spec.extra_bytes = 2;
  const std::string las = write_file("skip.las", make_las(spec, las_points(300, 2, 11)));
  const Cloud whole = read_cloud(las);
  const uint32_t record = whole.info.extra_bytes;
  for (uint64_t k : {0u, 1u, 137u, 299u, 300u, 1000u}) {
    auto src = mv::io::open_points(las);
    EXPECT_EQ(src->skip(k), std::min<uint64_t>(k, 300));
    PointColumns rest;
    while (src->next(rest, 64)) {}
    const uint64_t from = std::min<uint64_t>(k, 300);
    ASSERT_EQ(rest.size(), 300 - from) << k;
    EXPECT_TRUE(std::equal(rest.xyz.begin(), rest.xyz.end(), whole.points.xyz.begin() + 3 * from)) << k;
    EXPECT_TRUE(std::equal(rest.extra.begin(), rest.extra.end(), whole.points.extra.begin() + record * from)) << k;
  }
  std::vector<PlyColumn> cols{{"float", "x", {}}, {"float", "y", {}}, {"float", "z", {}}};
  for (int i = 0; i < 50; ++i)
    for (auto& c : cols) c.values.push_back(i * 0.5 + (c.name == "y"));
  for (Fmt fmt : {Fmt::le, Fmt::ascii}) {
    const std::string ply = write_file("skip.ply", make_cloud_ply(fmt, cols));
    auto src = mv::io::open_points(ply);
    EXPECT_EQ(src->skip(20), fmt == Fmt::ascii ? 0u : 20u);  // binary records are sought, ascii ones read
    PointColumns rest;
    while (src->next(rest, 7)) {}
    ASSERT_EQ(rest.size(), 30u);
    const Cloud all = read_cloud(ply);
    EXPECT_TRUE(std::equal(rest.xyz.begin(), rest.xyz.end(), all.points.xyz.begin() + 60));
  }
}

// A build over ranks: each opens a binary PLY with its slice, whose grid pass reads that slice alone, and the
// ranks' agreed extent gives the grid of the whole file.
TEST(PointReaders, PlySliceReadsItsShareForTheGrid) {
  std::vector<PlyColumn> cols{{"float", "x", {}}, {"float", "y", {}}, {"float", "z", {}}};
  for (int i = 0; i < 90; ++i)
    for (auto& c : cols) c.values.push_back(i < 30 ? 1000.0 + i : i * 0.25);  // the largest in the first third
  const std::string ply = write_file("slice.ply", make_cloud_ply(Fmt::le, cols));
  const Cloud all = read_cloud(ply);
  mv::io::PointReadOptions o;
  o.slice_part = 2;
  o.slice_parts = 3;
  double seen = -1;
  o.agree_extent = [&](double mine) {
    seen = mine;
    return 1089.0;  // what every rank's agree: the first third's largest
  };
  auto src = mv::io::open_points(ply, o);
  EXPECT_EQ(seen, 89 * 0.25);  // its slice's alone
  EXPECT_FALSE(src->read_whole_file());
  EXPECT_EQ(src->info().scale[0], all.info.scale[0]);
  EXPECT_EQ(src->skip(60), 60u);
  PointColumns rest;
  while (src->next(rest, 8)) {}
  ASSERT_EQ(rest.size(), 30u);
  EXPECT_TRUE(std::equal(rest.xyz.begin(), rest.xyz.end(), all.points.xyz.begin() + 180));
  o.slice_part = 0;
  o.slice_parts = 1;  // the whole file: read whole
  EXPECT_TRUE(mv::io::open_points(ply, o)->read_whole_file());
}

// ---------------------------------------------------------------------------------------------------
// PLY

std::vector<double> values(std::initializer_list<double> v) { return v; }

TEST(PlyPoints, AttributesInEveryFormat) {
  const std::vector<PlyColumn> cols = {
      {"float", "x", values({0.5, -1.25, 3, 0})},   {"uchar", "red", values({0, 128, 255, 7})},
      {"float", "y", values({2, 0.125, -8, 0})},    {"uchar", "green", values({1, 2, 3, 4})},
      {"float", "z", values({-0.75, 1, 2, 0})},     {"uchar", "blue", values({250, 251, 252, 253})},
      {"float", "quality", values({9, 9, 9, 9})},  // skipped
      {"float", "nx", values({0.25, 1, 0, -1})},    {"float", "ny", values({0.5, 0, 1, 0})},
      {"float", "nz", values({-0.125, 0, 0, 0.5})}, {"ushort", "intensity", values({0, 65535, 1000, 3})}};
  for (Fmt f : kAllFormats) {
    for (bool others : {false, true}) {
      SCOPED_TRACE(std::string(fmt_name(f)) + (others ? " with other elements" : ""));
      const Cloud c = read_cloud(write_file("attrs.ply", make_cloud_ply(f, cols, others)), 3);
      EXPECT_EQ(c.info.format, "PLY " + std::string(fmt_name(f)));
      EXPECT_EQ(c.info.points, 4u);
      EXPECT_EQ(c.batches, 2u);
      EXPECT_FALSE(c.info.z_up);
      EXPECT_EQ(c.info.attributes, mv::kPointRgb | mv::kPointNormal | mv::kPointIntensity);
      EXPECT_EQ(c.info.crs, "");
      const PointColumns& p = c.points;
      for (size_t i = 0; i < 4; ++i) {
        for (int a = 0; a < 3; ++a) {
          const double want = cols[size_t{2} * a].values[i];
          EXPECT_EQ(c.info.offset[a], 0);
          EXPECT_EQ(c.info.scale[a] * p.xyz[3 * i + a], want) << "vertex " << i;  // these floats lie on the grid
          EXPECT_EQ(p.rgb[3 * i + a], cols[size_t{2} * a + 1].values[i]);
          EXPECT_EQ(p.normal[3 * i + a], cols[7 + a].values[i]);
        }
        EXPECT_EQ(p.intensity[i], cols[10].values[i]);
      }
    }
  }
}

TEST(PlyPoints, SpellingsAndConversions) {
  const std::vector<PlyColumn> cols = {
      {"double", "x", values({1, 2, 3})},       {"double", "y", values({1, 2, 3})},
      {"double", "z", values({1, 2, 3})},       {"ushort", "r", values({1000, 65535, 0})},  // ushort as stored
      {"ushort", "g", values({1, 2, 3})},       {"ushort", "b", values({4, 5, 6})},
      {"float", "normal_x", values({1, 0, 0})}, {"float", "normal_y", values({0, 1, 0})},
      {"float", "normal_z", values({0, 0, 1})}, {"float", "scalar_intensity", values({3.6, -2, 1e6})}};
  const Cloud c = read_cloud(write_file("spell.ply", make_cloud_ply(Fmt::le, cols)));
  EXPECT_EQ(c.info.attributes, mv::kPointRgb | mv::kPointNormal | mv::kPointIntensity);
  EXPECT_EQ(c.points.rgb, (std::vector<uint16_t>{1000, 1, 4, 65535, 2, 5, 0, 3, 6}));
  EXPECT_EQ(c.points.normal, (std::vector<float>{1, 0, 0, 0, 1, 0, 0, 0, 1}));
  EXPECT_EQ(c.points.intensity, (std::vector<uint16_t>{4, 0, 65535}));  // rounded, clamped

  const std::vector<PlyColumn> other = {
      {"float", "x", values({1, 2, 3})},
      {"float", "y", values({1, 2, 3})},
      {"float", "z", values({1, 2, 3})},
      {"float", "diffuse_red", values({0.5, 1.5, -1})},  // float colours are fractions of 1
      {"float", "diffuse_green", values({0, 1, 0.2})},
      {"float", "diffuse_blue", values({1, 0, 0})},
      {"float", "nx", values({1, 0, 0})},  // a partial normal is skipped
      {"int", "scalar_Intensity", values({-5, 70000, 12})}};
  const Cloud d = read_cloud(write_file("spell2.ply", make_cloud_ply(Fmt::be, other)));
  EXPECT_EQ(d.info.attributes, mv::kPointRgb | mv::kPointIntensity);
  EXPECT_EQ(d.points.rgb, (std::vector<uint16_t>{128, 0, 255, 255, 255, 0, 0, 51, 0}));
  EXPECT_TRUE(d.points.normal.empty());
  EXPECT_EQ(d.points.intensity, (std::vector<uint16_t>{0, 65535, 12}));

  const std::vector<PlyColumn> lone_r = {{"float", "x", values({1})},
                                         {"float", "y", values({1})},
                                         {"float", "z", values({1})},
                                         {"float", "r", values({0.5})}};
  EXPECT_EQ(read_cloud(write_file("radius.ply", make_cloud_ply(Fmt::ascii, lone_r))).info.attributes, 0u);
}

// The mesh reader's fixture files (skipped elements with lists before, between and after the vertices, a
// list in the vertex element) read as points.
TEST(PlyPoints, ReadsMeshFiles) {
  using namespace mv::test::ply;
  for (Fmt f : kAllFormats) {
    for (bool vertex_list : {false, true}) {
      SCOPED_TRACE(std::string(fmt_name(f)) + (vertex_list ? " with a vertex list" : ""));
      MeshSpec m = small_mesh();
      m.extras = true;
      m.vertex_list = vertex_list;
      const Cloud c = read_cloud(write_file("mesh.ply", make_ply(m, f)), 2);
      ASSERT_EQ(c.points.size(), m.vertices.size());
      EXPECT_EQ(c.info.attributes, mv::kPointRgb);  // the fixture's lone nx is not a normal
      for (size_t i = 0; i < m.vertices.size(); ++i)
        for (int a = 0; a < 3; ++a) {
          EXPECT_EQ(c.info.scale[a] * c.points.xyz[3 * i + a], m.vertices[i][a]);
          EXPECT_EQ(c.points.rgb[3 * i + a], 200 + a);
        }
    }
  }
}

TEST(PlyPoints, GridScaleRule) {
  EXPECT_EQ(mv::io::ply_grid_scale(PlyGrid::float32, 0), 1);
  EXPECT_EQ(mv::io::ply_grid_scale(PlyGrid::integer, 1e9), 1);
  EXPECT_EQ(mv::io::ply_grid_scale(PlyGrid::float32, 1), std::ldexp(1.0, 1 - 24));      // 2^0 <= 1 < 2^1
  EXPECT_EQ(mv::io::ply_grid_scale(PlyGrid::float32, 1000), std::ldexp(1.0, 10 - 24));  // 2^9 <= 1000 < 2^10
  EXPECT_EQ(mv::io::ply_grid_scale(PlyGrid::float64, 0.75), std::ldexp(1.0, 0 - 30));
  EXPECT_EQ(mv::io::ply_grid_scale(PlyGrid::float64, 5e-324), std::ldexp(1.0, -1074));  // subnormal
  EXPECT_EQ(mv::io::ply_grid_scale(PlyGrid::float64, 1.7e308), std::ldexp(1.0, 1024 - 30));
}

// Every coordinate comes back within scale/2, the grid chosen as ply_points.h says.
void expect_grid(const std::string& type, double magnitude, Fmt f, uint64_t seed, double want_scale, double max_x) {
  SCOPED_TRACE(type + " " + std::to_string(magnitude) + " " + fmt_name(f));
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-magnitude, magnitude);
  std::vector<PlyColumn> cols = {{type, "x", {}}, {type, "y", {}}, {type, "z", {}}};
  double m = 0;
  for (int i = 0; i < 500; ++i)
    for (auto& c : cols) {
      double v = u(rng);
      if (type == "float") v = static_cast<float>(v);
      if (type != "float" && type != "double") v = std::round(v);
      c.values.push_back(v);
      m = std::max(m, std::fabs(v));
    }
  if (want_scale == 0) {  // the float rule: 2^(e-24) or 2^(e-30) for 2^(e-1) <= m < 2^e
    int e = 0;
    std::frexp(m, &e);
    want_scale = std::ldexp(1.0, e - (type == "float" ? 24 : 30));
  }
  const Cloud c = read_cloud(write_file("grid.ply", make_cloud_ply(f, cols)), 128);
  for (int a = 0; a < 3; ++a) {
    ASSERT_EQ(c.info.scale[a], want_scale);
    ASSERT_EQ(c.info.offset[a], 0);
  }
  for (size_t i = 0; i < 500; ++i)
    for (int a = 0; a < 3; ++a) {
      const double x = c.points.xyz[3 * i + a];
      ASSERT_LE(std::fabs(x), max_x);
      ASSERT_LE(std::fabs(x * want_scale - cols[a].values[i]), want_scale / 2) << "vertex " << i;
    }
}

TEST(PlyPoints, QuantizationRule) {
  uint64_t seed = 1;
  for (Fmt f : kAllFormats) {
    for (double mag : {1e-30, 1e-3, 1.0, 1000.0, 3e7, 1e30}) {
      expect_grid("float", mag, f, ++seed, 0, std::ldexp(1.0, 24));
      expect_grid("double", mag, f, ++seed, 0, std::ldexp(1.0, 30));
    }
    expect_grid("int", 2e9, f, ++seed, 1, 2147483647);  // integers below 2^31: scale 1
    expect_grid("short", 30000, f, ++seed, 1, 32767);
  }
  // Integers from 2^31 take the double rule; all-zero clouds scale 1.
  std::vector<PlyColumn> big = {
      {"uint", "x", values({4e9, 1})}, {"uint", "y", values({0, 3})}, {"uint", "z", values({2, 2})}};
  const Cloud c = read_cloud(write_file("big.ply", make_cloud_ply(Fmt::le, big)));
  EXPECT_EQ(c.info.scale[0], std::ldexp(1.0, 32 - 30));
  EXPECT_EQ(c.points.xyz[0], 1000000000);
  std::vector<PlyColumn> zero = {
      {"float", "x", values({0, -0.0})}, {"float", "y", values({0, 0})}, {"float", "z", values({0, 0})}};
  EXPECT_EQ(read_cloud(write_file("zero.ply", make_cloud_ply(Fmt::ascii, zero))).info.scale[1], 1);
  // A float cloud's largest values are exact.
  std::vector<PlyColumn> exact = {{"float", "x", values({1000.123f, -999.0f})},
                                  {"float", "y", values({0, 1})},
                                  {"float", "z", values({0.000123f, 2})}};
  const Cloud e = read_cloud(write_file("exact.ply", make_cloud_ply(Fmt::le, exact)));
  EXPECT_EQ(e.info.scale[0] * e.points.xyz[0], static_cast<double>(1000.123f));
  EXPECT_EQ(e.info.scale[0] * e.points.xyz[3], -999.0);
}

// Binary records with x, y, z of one float type take a typed fast path; ascii, and mixed coordinate types,
// the generic walk. Both give the same columns, halves between grid steps included.
TEST(PlyPoints, FastPathEqualsGenericWalk) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-100, 100);
  for (const std::string type : {"float", "double"}) {
    std::vector<PlyColumn> cols = {{type, "x", {}}, {"uchar", "red", {}}, {type, "y", {}},
                                   {"uchar", "green", {}}, {type, "z", {}}, {"uchar", "blue", {}},
                                   {"float", "nx", {}}, {"float", "ny", {}}, {"float", "nz", {}}};
    for (int i = 0; i < 3000; ++i)
      for (size_t k = 0; k < cols.size(); ++k) {
        double v = k % 2 == 1 && k < 6 ? std::floor(u(rng) + 100) : u(rng);
        if (k == 0 && i % 3 == 0) v = (std::floor(v) + 0.5) * std::ldexp(1.0, type == "float" ? 7 - 24 : 7 - 30);
        if (cols[k].type == "float") v = static_cast<float>(v);
        cols[k].values.push_back(v);
      }
    cols[0].values[0] = 100;  // the extent, so that the half-step values above lie between grid steps
    std::vector<PlyColumn> mixed = cols;
    mixed[2].type = type == "float" ? "double" : "float";
    mixed[2].values = cols[2].values;
    for (double& v : mixed[2].values) v = static_cast<float>(v);
    for (const auto* set : {&cols, &mixed}) {
      SCOPED_TRACE(type + (set == &mixed ? " mixed" : ""));
      const Cloud ascii = read_cloud(write_file("fast.ply", make_cloud_ply(Fmt::ascii, *set)), 1000);
      for (Fmt f : {Fmt::le, Fmt::be}) {
        const Cloud b = read_cloud(write_file("fast.ply", make_cloud_ply(f, *set)), 1000);
        EXPECT_EQ(b.info.scale[0], ascii.info.scale[0]);
        EXPECT_EQ(b.points.xyz, ascii.points.xyz);
        EXPECT_EQ(b.points.rgb, ascii.points.rgb);
        EXPECT_EQ(b.points.normal, ascii.points.normal);
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------------
// Staged real clouds (shared/data/README.md)

// The shared file, or "" after one line saying it is absent (a user's machine has no shared data).
std::string staged(const std::string& relative) {
  const std::string path = mv::test::shared_data_file(relative);
  if (path.empty())
    std::printf("shared data not found: %s (stage ../shared/data or set MEGAVOX_TEST_DATA); not checked\n",
                mv::test::shared_data_path(relative).c_str());
  return path;
}

TEST(PointReaders, AutzenLasMatchesItsPly) {
  const std::string las = staged("pointcloud_autzen/autzen_trim.las");
  const std::string ply = staged("pointcloud_autzen/autzen_trim.ply");
  if (las.empty() || ply.empty()) return;
  const Cloud a = read_cloud(las, 8191);
  const Cloud b = read_cloud(ply, 10000);
  EXPECT_EQ(a.info.format, "LAS 1.2, point format 3");
  EXPECT_EQ(a.info.attributes, mv::kPointRgb | mv::kPointIntensity | mv::kPointExtra);
  EXPECT_NE(a.info.crs.find("NAD83"), std::string::npos) << a.info.crs;
  EXPECT_EQ(b.info.attributes, mv::kPointRgb);
  ASSERT_EQ(a.points.size(), 110000u);
  ASSERT_EQ(b.points.size(), 110000u);
  const double shift[3] = {636000, 848900, 400};  // the PLY's offset (its comment line)
  double worst = 0;
  uint64_t rgb_differ = 0;
  for (size_t i = 0; i < 110000; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double from_las = a.info.offset[k] + a.info.scale[k] * a.points.xyz[3 * i + k] - shift[k];
      const double from_ply = b.info.offset[k] + b.info.scale[k] * b.points.xyz[3 * i + k];
      worst = std::max(worst, std::fabs(from_las - from_ply));
      rgb_differ += a.points.rgb[3 * i + k] != b.points.rgb[3 * i + k];
    }
  }
  std::printf("autzen: largest difference of a LAS and a PLY coordinate %.3g (of 330000)\n", worst);
  EXPECT_LE(worst, 1e-3);
  EXPECT_EQ(rgb_differ, 0u);
}

TEST(PointReaders, LionTakanawaCount) {
  const std::string ply = staged("pointcloud_lion_takanawa/lion_takanawa.ply");
  if (ply.empty()) return;
  const Cloud c = read_cloud(ply, 1 << 16);
  EXPECT_EQ(c.info.points, 341989u);
  EXPECT_EQ(c.points.size(), 341989u);
  EXPECT_EQ(c.info.attributes, mv::kPointRgb);
}

}  // namespace
