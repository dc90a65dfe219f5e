// The point reader test fixture (point_fixture.h): a LAS writer following the ASPRS layout of every version
// and point format, a PLY cloud writer, and reading a cloud back.
#include "point_fixture.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <exception>
#include <random>

#include "megavox/error.h"

namespace mv::test::points {

namespace {

// Little-endian bytes of a LAS file.
class LasBytes {
 public:
  template <class T>
  void put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if constexpr (std::endian::native == std::endian::big) std::reverse(b, b + sizeof(T));
    out.append(b, sizeof(T));
  }
  void text(const std::string& s, size_t n) {  // NUL-padded
    std::string t = s.substr(0, n);
    t.resize(n, '\0');
    out += t;
  }
  template <class T>
  void put_at(size_t at, T v) {
    LasBytes b;
    b.put(v);
    out.replace(at, sizeof(T), b.out);
  }
  std::string out;
};

std::string vlr(bool extended, uint16_t record_id, const std::string& payload) {
  LasBytes b;
  b.put<uint16_t>(0);
  b.text("LASF_Projection", 16);
  b.put<uint16_t>(record_id);
  if (extended)
    b.put<uint64_t>(payload.size());
  else
    b.put<uint16_t>(static_cast<uint16_t>(payload.size()));
  b.text("written by point_fixture", 32);
  return b.out + payload;
}

std::string geokeys(uint16_t crs) {
  LasBytes b;
  for (uint16_t w : {1, 1, 0, 3}) b.put(w);        // directory version, revision, minor, 3 keys
  for (uint16_t w : {1024, 0, 1, 1}) b.put(w);     // GTModelTypeGeoKey = projected
  for (uint16_t w : {2048, 0, 1, 4269}) b.put(w);  // GeographicTypeGeoKey = NAD83
  for (uint16_t w : {3072, 0, 1}) b.put(w);        // ProjectedCSTypeGeoKey = crs
  b.put(crs);
  return b.out;
}

}  // namespace

uint16_t las_record_length(int format) {
  static constexpr uint16_t kLength[] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};
  return format >= 0 && format < 11 ? kLength[format] : 20;
}

std::vector<LasPoint> las_points(size_t n, uint16_t extra_bytes, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<LasPoint> pts(n);
  for (size_t i = 0; i < n; ++i) {
    LasPoint& p = pts[i];
    for (int a = 0; a < 3; ++a) p.xyz[a] = static_cast<int32_t>(rng());
    if (i == 0) p.xyz[0] = INT32_MIN, p.xyz[1] = INT32_MAX, p.xyz[2] = 0;
    p.intensity = static_cast<uint16_t>(rng());
    for (auto& c : p.rgb) c = static_cast<uint16_t>(rng());
    p.classification = static_cast<uint8_t>(rng());
    p.gps_time = static_cast<double>(rng() % 1000000) / 7;
    p.nir = static_cast<uint16_t>(rng());
    for (uint16_t k = 0; k < extra_bytes; ++k) p.extra.push_back(static_cast<uint8_t>(rng()));
  }
  return pts;
}

std::string make_las(const LasSpec& s, const std::vector<LasPoint>& points) {
  const uint16_t header = s.minor >= 4 ? 375 : s.minor == 3 ? 235 : 227;
  const uint16_t record = static_cast<uint16_t>(las_record_length(s.format) + s.extra_bytes);
  std::vector<std::string> vlrs;
  if (!s.wkt.empty() && !s.wkt_in_evlr) vlrs.push_back(vlr(false, 2112, s.wkt + '\0'));
  if (s.geokey_crs) vlrs.push_back(vlr(false, 34735, geokeys(s.geokey_crs)));
  size_t vlr_bytes = 0;
  for (const auto& v : vlrs) vlr_bytes += v.size();
  const uint32_t point_offset = static_cast<uint32_t>(header + vlr_bytes + s.gap);
  const uint64_t n = points.size();

  LasBytes b;
  b.out = "LASF";
  b.put<uint16_t>(7);                                        // file source id
  b.put<uint16_t>(s.minor >= 4 && !s.wkt.empty() ? 16 : 0);  // global encoding: the WKT bit
  b.text("", 16);                                            // project GUID
  b.put<uint8_t>(1);
  b.put<uint8_t>(static_cast<uint8_t>(s.minor));
  b.text("megavox test", 32);
  b.text("point_fixture", 32);
  b.put<uint16_t>(100);
  b.put<uint16_t>(2024);
  b.put<uint16_t>(header);
  b.put<uint32_t>(point_offset);
  b.put<uint32_t>(static_cast<uint32_t>(vlrs.size()));
  b.put<uint8_t>(static_cast<uint8_t>(s.format));
  b.put<uint16_t>(record);
  b.put<uint32_t>(s.minor >= 4 && s.format >= 6 ? 0 : static_cast<uint32_t>(n));  // legacy count
  for (int r = 0; r < 5; ++r)
    b.put<uint32_t>(r == 0 && !(s.minor >= 4 && s.format >= 6) ? static_cast<uint32_t>(n) : 0);
  for (double v : s.scale) b.put(v);
  for (double v : s.offset) b.put(v);
  for (int a = 0; a < 3; ++a) {
    b.put(s.offset[a] + 1000);  // max (not checked by the reader)
    b.put(s.offset[a] - 1000);  // min
  }
  if (s.minor >= 3) b.put<uint64_t>(0);  // start of waveform data
  size_t evlr_start_at = 0;
  if (s.minor >= 4) {
    evlr_start_at = b.out.size();
    b.put<uint64_t>(0);  // start of the first EVLR, patched below
    b.put<uint32_t>(!s.wkt.empty() && s.wkt_in_evlr ? 1 : 0);
    b.put<uint64_t>(n);
    for (int r = 0; r < 15; ++r) b.put<uint64_t>(r == 0 ? n : 0);
  }
  EXPECT_EQ(b.out.size(), header);
  for (const auto& v : vlrs) b.out += v;
  b.out.append(s.gap, 'g');
  EXPECT_EQ(b.out.size(), point_offset);

  const int f = s.format;
  for (const LasPoint& p : points) {
    const size_t start = b.out.size();
    for (int32_t v : p.xyz) b.put(v);
    b.put(p.intensity);
    if (f < 6) {
      b.put<uint8_t>(0x11);  // return 1 of 1
      b.put(p.classification);
      b.put<int8_t>(-12);   // scan angle rank
      b.put<uint8_t>(9);    // user data
      b.put<uint16_t>(77);  // point source id
      if (f == 1 || f == 3 || f == 4 || f == 5) b.put(p.gps_time);
      if (f == 2 || f == 3 || f == 5)
        for (uint16_t c : p.rgb) b.put(c);
    } else {
      b.put<uint8_t>(0x11);
      b.put<uint8_t>(0x40);  // scanner channel 1
      b.put(p.classification);
      b.put<uint8_t>(9);
      b.put<int16_t>(-1200);  // scan angle
      b.put<uint16_t>(77);
      b.put(p.gps_time);
      if (f >= 7 && f != 9)
        for (uint16_t c : p.rgb) b.put(c);
      if (f == 8 || f == 10) b.put(p.nir);
    }
    b.out.resize(start + las_record_length(f), 'w');  // waveform fields of formats 4, 5, 9, 10 as filler
    for (uint16_t k = 0; k < s.extra_bytes; ++k) b.put<uint8_t>(k < p.extra.size() ? p.extra[k] : 0);
  }
  if (!s.wkt.empty() && s.wkt_in_evlr && s.minor >= 4) {
    b.put_at<uint64_t>(evlr_start_at, b.out.size());
    b.out += vlr(true, 2112, s.wkt + '\0');
  }
  return b.out;
}

std::string make_cloud_ply(ply::Fmt f, const std::vector<PlyColumn>& columns, bool others) {
  const size_t n = columns.empty() ? 0 : columns[0].values.size();
  std::string h = "ply\nformat " + std::string(ply::fmt_name(f)) + " 1.0\ncomment made by point_fixture\n";
  ply::BodyWriter w(f);
  if (others) {
    h += "element camera 1\nproperty list uchar float view\nproperty int id\n";
    w.put("uchar", 2);
    w.put("float", 0.5);
    w.put("float", -0.5);
    w.put("int", 3);
    w.end_entry();
  }
  h += "element vertex " + std::to_string(n) + "\n";
  for (const PlyColumn& c : columns) h += "property " + c.type + " " + c.name + "\n";
  for (size_t i = 0; i < n; ++i) {
    for (const PlyColumn& c : columns) w.put(c.type, c.values[i]);
    w.end_entry();
  }
  if (others) {
    h += "element face 1\nproperty list uchar int vertex_indices\n";
    w.put("uchar", 3);
    for (int k = 0; k < 3; ++k) w.put("int", k);
    w.end_entry();
  }
  return h + "end_header\n" + w.bytes();
}

Cloud read_cloud(const std::string& path, size_t batch, const io::PointReadOptions& options) {
  Cloud c;
  auto src = io::open_points(path, options);
  c.info = src->info();
  while (src->next(c.points, batch)) ++c.batches;
  EXPECT_EQ(c.points.size(), c.info.points);
  EXPECT_FALSE(src->next(c.points, batch));  // stays at the end
  return c;
}

std::string read_error(const std::string& name, const std::string& bytes, size_t batch) {
  const std::string path = ply::write_file(name, bytes);
  try {
    auto src = io::open_points(path);
    PointColumns cols;
    while (src->next(cols, batch)) {
    }
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an mv::Error: " << e.what();
    return "other exception";
  }
  return "";
}

BuildOptions cloud_build_options(const std::string& input, const std::string& output, uint32_t resolution,
                                 Encoding encoding) {
  BuildOptions o;
  o.input = input;
  o.output = output;
  o.resolution = resolution;
  o.encoding = encoding;
  o.placement = parse_grid_origin("min");
  return o;
}

}  // namespace mv::test::points
