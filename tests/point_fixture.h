// What the point reader tests share: LAS files of any version and point format written from a description,
// PLY point clouds with any vertex properties, and reading a file back completely.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/point_source.h"
#include "megavox/build.h"
#include "megavox/points.h"
#include "ply_fixture.h"

namespace mv::test::points {

// One LAS point: the fields the reader delivers, and a few it skips (to see that it does).
struct LasPoint {
  int32_t xyz[3] = {};
  uint16_t intensity = 0;
  uint16_t rgb[3] = {};
  uint8_t classification = 0;
  double gps_time = 0;
  uint16_t nir = 0;
  std::vector<uint8_t> extra;
};

struct LasSpec {
  int minor = 2;   // LAS 1.minor
  int format = 3;  // point data record format, written as is (also unsupported ones)
  uint16_t extra_bytes = 0;
  double scale[3] = {0.01, 0.001, 0.25};
  double offset[3] = {636000.5, -20, 3};
  std::string wkt;  // as an OGC WKT record (VLR, or EVLR with wkt_in_evlr on LAS 1.4)
  bool wkt_in_evlr = false;
  uint16_t geokey_crs = 0;  // a GeoKeyDirectory with ProjectedCSTypeGeoKey = this, when not 0
  uint32_t gap = 0;         // bytes between the last VLR and the point data
};

// Deterministic points with every field set (extra bytes included).
std::vector<LasPoint> las_points(size_t n, uint16_t extra_bytes, uint64_t seed);

// The bytes of a LAS file.
std::string make_las(const LasSpec& spec, const std::vector<LasPoint>& points);

// Standard record length of a point format (0-10), as the LAS 1.4 specification lists them.
uint16_t las_record_length(int format);

// A PLY cloud: one vertex property per column (type, name, a value per point).
struct PlyColumn {
  std::string type, name;
  std::vector<double> values;
};

// The PLY file of `columns` in format `f`; with `others`, a skipped element before the vertices and a face
// element after them.
std::string make_cloud_ply(ply::Fmt f, const std::vector<PlyColumn>& columns, bool others = false);

struct Cloud {
  PointCloudInfo info;
  PointColumns points;
  size_t batches = 0;
};

// Everything in `path` through open_points, in batches of `batch` points.
Cloud read_cloud(const std::string& path, size_t batch = 1000, const io::PointReadOptions& options = {});

// The mv::Error message of reading `bytes` completely ("" when it reads fine); any other exception fails.
std::string read_error(const std::string& name, const std::string& bytes, size_t batch = 1000);

// Options building the cloud `input` into `output` at `resolution` voxels with --grid-origin min, in `encoding`.
BuildOptions cloud_build_options(const std::string& input, const std::string& output, uint32_t resolution,
                                 Encoding encoding);

}  // namespace mv::test::points
