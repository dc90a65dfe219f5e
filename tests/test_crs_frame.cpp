// The frame that places a georeferenced cloud on the globe (io/crs_frame.h) against PROJ's own transform of the
// same points to EPSG:4978: Autzen's Oregon Lambert in feet from the LAS file's WKT, UTM in metres, geographic
// degrees, compound CRSs' vertical units, EPSG:4978 itself, and CRSs that must be refused.
#include <gtest/gtest.h>
#include <proj.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

#include "io/crs_frame.h"
#include "megavox/error.h"
#include "test_support.h"

namespace mv::test {
namespace {

// PROJ's direct transform of points in `crs` (x east, y north) to EPSG:4978; z is fed as given (metres).
struct CrsDirectProj {
  PJ_CONTEXT* ctx = proj_context_create();
  PJ* op = nullptr;
  explicit CrsDirectProj(const std::string& crs) {
    PJ* raw = proj_create_crs_to_crs(ctx, crs.c_str(), "EPSG:4978", nullptr);
    if (raw) op = proj_normalize_for_visualization(ctx, raw);
    proj_destroy(raw);
  }
  ~CrsDirectProj() {
    proj_destroy(op);
    proj_context_destroy(ctx);
  }
  void to_ecef(double x, double y, double z, double out[3]) const {
    PJ_COORD r = proj_trans(op, PJ_FWD, proj_coord(x, y, z, 0));
    out[0] = r.xyz.x;
    out[1] = r.xyz.y;
    out[2] = r.xyz.z;
  }
};

// transform * ((p - centre) * units_to_metres): a point as the tileset writer places it.
void crs_frame_point(const io::CrsFrame& f, const double centre[3], const double p[3], double out[3]) {
  double l[3];
  for (int k = 0; k < 3; ++k) l[k] = (p[k] - centre[k]) * f.units_to_metres[k];
  for (int k = 0; k < 3; ++k)
    out[k] = f.transform[12 + k] + f.transform[k] * l[0] + f.transform[4 + k] * l[1] + f.transform[8 + k] * l[2];
}

// |a - b| perpendicular to the (normalized) up direction.
double crs_horizontal(const double a[3], const double b[3], const double up[3]) {
  const double n = std::sqrt(up[0] * up[0] + up[1] * up[1] + up[2] * up[2]);
  double d[3], v = 0, dd = 0;
  for (int k = 0; k < 3; ++k) d[k] = a[k] - b[k], v += d[k] * up[k] / n, dd += d[k] * d[k];
  return std::sqrt(std::max(0.0, dd - v * v));
}

// The header numbers and the OGC WKT record (LASF_Projection 2112) of a LAS file.
struct CrsLasFile {
  std::string wkt;
  double centre[3] = {}, half[3] = {};
};
CrsLasFile crs_read_las(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<char> b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto f64 = [&](size_t at) { double v; std::memcpy(&v, &b[at], 8); return v; };
  auto u16 = [&](size_t at) { uint16_t v; std::memcpy(&v, &b[at], 2); return v; };
  auto u32 = [&](size_t at) { uint32_t v; std::memcpy(&v, &b[at], 4); return v; };
  CrsLasFile r;
  if (b.size() < 227) return r;
  for (int k = 0; k < 3; ++k) {
    const double mx = f64(179 + 16 * k), mn = f64(187 + 16 * k);
    r.centre[k] = (mx + mn) / 2;
    r.half[k] = (mx - mn) / 2;
  }
  size_t at = u16(94);
  for (uint32_t i = 0, n = u32(100); i < n && at + 54 <= b.size(); ++i) {
    const std::string user(&b[at + 2], strnlen(&b[at + 2], 16));
    const uint16_t record = u16(at + 18), length = u16(at + 20);
    if (user == "LASF_Projection" && record == 2112 && at + 54 + length <= b.size()) {
      r.wkt.assign(&b[at + 54], length);
      r.wkt.resize(strnlen(r.wkt.c_str(), r.wkt.size()));
      break;
    }
    at += 54 + size_t(length);
  }
  return r;
}

TEST(CrsFrame, AutzenLambertFeetMatchesProj) {
  MV_SKIP_WITHOUT_SHARED_DATA("pointcloud_autzen/autzen_trim.las");
  const CrsLasFile las = crs_read_las(shared_data_file("pointcloud_autzen/autzen_trim.las"));
  ASSERT_FALSE(las.wkt.empty()) << "no OGC WKT record in the file";
  const io::CrsFrame f = io::crs_frame(las.wkt, las.centre);
  // International feet, heights too (a 2D projected CRS: heights in its unit).
  for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(f.units_to_metres[k], 0.3048);
  const double* up = &f.transform[8];

  // The origin is PROJ's own transform of the centre (heights fed in metres, as the frame reads them).
  CrsDirectProj direct(las.wkt);
  ASSERT_NE(direct.op, nullptr);
  double want[3];
  direct.to_ecef(las.centre[0], las.centre[1], las.centre[2] * 0.3048, want);
  const double centre_error = crs_horizontal(&f.transform[12], want, up);
  EXPECT_LT(centre_error, 1.0);

  // On the ground at Autzen Stadium, Eugene, Oregon.
  double lat, lon;
  {
    PJ_CONTEXT* ctx = proj_context_create();
    PJ* geo = proj_create_crs_to_crs(ctx, "EPSG:4978", "EPSG:4979", nullptr);
    PJ_COORD g = proj_trans(geo, PJ_FWD, proj_coord(f.origin_ecef[0], f.origin_ecef[1], f.origin_ecef[2], 0));
    lat = g.v[0], lon = g.v[1];
    proj_destroy(geo);
    proj_context_destroy(ctx);
  }
  EXPECT_NEAR(lat, 44.05, 0.05);
  EXPECT_NEAR(lon, -123.07, 0.05);
  // West of the Lambert's central meridian (-120.5): grid north turns west, by (lon + 120.5) sin(44.27).
  EXPECT_NEAR(f.convergence_degrees, (lon + 120.5) * std::sin(44.27 * std::numbers::pi / 180), 0.02);
  EXPECT_NEAR(f.scale, 1.0, 1e-3);

  // The bounding box's corners, as the writer places them, within the bound the frame states.
  double vertical = 0;
  const double bound = io::crs_frame_error_metres(las.wkt, las.centre, las.half, &vertical);
  EXPECT_LT(bound, 0.5);
  double worst = 0;
  for (int c = 0; c < 8; ++c) {
    double p[3], got[3];
    for (int k = 0; k < 3; ++k) p[k] = las.centre[k] + ((c >> k) & 1 ? las.half[k] : -las.half[k]);
    crs_frame_point(f, las.centre, p, got);
    direct.to_ecef(p[0], p[1], p[2] * 0.3048, want);
    worst = std::max(worst, crs_horizontal(got, want, up));
  }
  EXPECT_LE(worst, bound + 1e-6);
  std::printf("Autzen: %s, convergence %.4f deg, scale %.7f; centre vs PROJ %.3g m; corners %.3g m; bound over "
              "+-(%.0f, %.0f, %.0f) ft: %.3g m horizontal, %.3g m vertical\n",
              f.crs_name.c_str(), f.convergence_degrees, f.scale, centre_error, worst, las.half[0], las.half[1],
              las.half[2], bound, vertical);
}

TEST(CrsFrame, UtmMetresMatchesProj) {
  // On UTM 10N's central meridian (-123 deg), 4,876 km north: there grid north is true north and k = 0.9996.
  const double centre[3] = {500000, 4876000, 100};
  const io::CrsFrame f = io::crs_frame("EPSG:32610", centre);
  EXPECT_EQ(f.crs_name, "WGS 84 / UTM zone 10N");
  for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(f.units_to_metres[k], 1.0);
  EXPECT_NEAR(std::atan2(f.origin_ecef[1], f.origin_ecef[0]) * 180 / std::numbers::pi, -123.0, 1e-9);
  EXPECT_NEAR(f.convergence_degrees, 0.0, 1e-6);
  EXPECT_NEAR(f.scale, 0.9996 / (1 + 100 / 6.37e6), 2e-6);  // k over the height factor

  CrsDirectProj direct("EPSG:32610");
  double want[3];
  direct.to_ecef(centre[0], centre[1], centre[2], want);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(f.origin_ecef[k], want[k], 1e-6);
  const double half[3] = {1000, 1000, 50};
  const double bound = io::crs_frame_error_metres("EPSG:32610", centre, half);
  EXPECT_LT(bound, 0.05);
  for (int c = 0; c < 8; ++c) {
    double p[3], got[3];
    for (int k = 0; k < 3; ++k) p[k] = centre[k] + ((c >> k) & 1 ? half[k] : -half[k]);
    crs_frame_point(f, centre, p, got);
    direct.to_ecef(p[0], p[1], p[2], want);
    EXPECT_LE(crs_horizontal(got, want, &f.transform[8]), bound + 1e-6);
  }
  // East of the central meridian in the north, grid north turns east.
  const double east_centre[3] = {600000, 4876000, 100};
  EXPECT_GT(io::crs_frame("EPSG:32610", east_centre).convergence_degrees, 0.5);
}

TEST(CrsFrame, GeographicDegreesInLasOrder) {
  // EPSG:4326 is latitude first; a LAS file stores longitude as x.
  const double centre[3] = {-123.07, 44.05, 100};
  const io::CrsFrame f = io::crs_frame("EPSG:4326", centre);
  EXPECT_NEAR(std::atan2(f.origin_ecef[1], f.origin_ecef[0]) * 180 / std::numbers::pi, -123.07, 1e-9);
  EXPECT_NEAR(f.units_to_metres[0], 111320 * std::cos(44.05 * std::numbers::pi / 180), 200);
  EXPECT_NEAR(f.units_to_metres[1], 111120, 200);
  const double half[3] = {0.005, 0.005, 50};  // about 400 m by 550 m
  EXPECT_LT(io::crs_frame_error_metres("EPSG:4326", centre, half), 0.1);
}

TEST(CrsFrame, CompoundTakesTheVerticalUnit) {
  const double centre[3] = {1000000, 800000, 400};
  EXPECT_DOUBLE_EQ(io::crs_frame("EPSG:6557+8228", centre).units_to_metres[2], 0.3048);  // NAVD88 height (ft)
  EXPECT_DOUBLE_EQ(io::crs_frame("EPSG:2992+5703", centre).units_to_metres[2], 1.0);     // NAVD88 height (m)
  EXPECT_DOUBLE_EQ(io::crs_frame("EPSG:2992", centre).units_to_metres[2], 0.3048);       // 2D: horizontal unit
}

TEST(CrsFrame, GeocentricIsItsOwnFrame) {
  const double centre[3] = {-2505579.67, -3847781.35, 4412242.26};
  const io::CrsFrame f = io::crs_frame("EPSG:4978", centre);
  const double p[3] = {centre[0] + 123, centre[1] - 45, centre[2] + 67};
  double got[3];
  crs_frame_point(f, centre, p, got);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(got[k], p[k], 1e-6);
  const double half[3] = {500, 500, 500};
  EXPECT_LT(io::crs_frame_error_metres("EPSG:4978", centre, half), 1e-6);
}

TEST(CrsFrame, RefusesWhatIsNoEarthCrs) {
  const double centre[3] = {0, 0, 0};
  for (const char* crs : {"nonsense", "EPSG:99999", "EPSG:5703",
                          "LOCAL_CS[\"site\",LOCAL_DATUM[\"site\",0],UNIT[\"metre\",1],AXIS[\"X\",EAST],"
                          "AXIS[\"Y\",NORTH]]",
                          ""}) {
    SCOPED_TRACE(crs);
    const std::string m = error_message([&] { io::crs_frame(crs, centre); });
    EXPECT_NE(m.find("cannot place the cloud on the globe"), std::string::npos) << m;
    EXPECT_NE(m.find(std::string(crs).substr(0, 20)), std::string::npos) << "the message names the CRS: " << m;
  }
}

}  // namespace
}  // namespace mv::test
