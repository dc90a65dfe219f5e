// 3D Tiles 1.1 output of point hierarchies: every .glb tile read back by hand (tiles3d_read.h: meshopt views
// decoded by meshoptimizer, the node's transform applied) against the hierarchy it came from, properties and
// feature IDs included; the root transform against PROJ's own transform to EPSG:4978, on synthetic clouds and on
// Autzen's LAS file (Oregon Lambert, feet) built through `points build`.
#include <proj.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>

#include "io/tiles3d_writer.h"
#include "megavox/point_build.h"
#include "test_support.h"
#include "tiles3d_fixture.h"
#include "tiles3d_read.h"

namespace mv::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;



// The tileset's local frame as asset.extras states it: p_local = (world - origin) * units_to_metres.
struct V11Frame {
  double origin[3], units[3];
  double local(const PointHierarchy& h, uint64_t point, int a) const {
    const double world = h.source.offset[a] + h.source.scale[a] * double(h.points.xyz[3 * point + a]);
    return (world - origin[a]) * units[a];
  }
};

struct V11Seen {
  uint64_t leaf_points = 0, tiles = 0, files = 0, feature_tiles = 0;
};

// Tile `t` against node `i`: box, error, content (positions, colours, properties, feature IDs), then children.
void v11_check_tile(const PointHierarchy& h, const std::string& dir, int colour_shift, const V11Frame& f,
                    const json& t, size_t i, double parent_error, V11Seen& seen) {
  const PointNode& n = h.nodes[i];
  SCOPED_TRACE("tile " + tile_name(n.code, n.level));
  ++seen.tiles;
  const double error = t.at("geometricError");
  expect_error_falls(n, error, parent_error);
  const std::vector<double> box = t.at("boundingVolume").at("box");
  ASSERT_EQ(box.size(), 12u);
  double c[3], half[3];
  for (int a = 0; a < 3; ++a) c[a] = box[a], half[a] = box[3 + 4 * a];
  if (i != 0) {  // a child's box is its cube, in the local frame's units
    for (int a = 0; a < 3; ++a)
      EXPECT_NEAR(half[a], std::abs(h.source.scale[a] * f.units[a]) * std::ldexp(1.0, int(20 + h.shift - n.level)),
                  1e-9 * half[a]);
  }
  if (n.point_count == 0) {
    EXPECT_FALSE(t.contains("content"));
  } else {
    const std::string uri = t.at("content").at("uri");
    EXPECT_EQ(uri, "tiles/" + tile_name(n.code, n.level) + ".glb");
    const GlbRead g = read_glb(dir + "/" + uri);
    ++seen.files;
    ASSERT_EQ(g.points, n.point_count);
    const bool rgb = h.source.attributes & kPointRgb;
    ASSERT_EQ(g.rgb.size(), rgb ? 3ull * n.point_count : 0u);
    // Half a quantization step, plus the float the encoder is handed (the local frame's position).
    const double extent = 2 * std::max({half[0], half[1], half[2]});
    for (uint64_t k = 0; k < n.point_count; ++k) {
      for (int a = 0; a < 3; ++a) {
        const double want = f.local(h, n.first_point + k, a);
        const double tolerance = g.step * 0.5 + std::abs(want) * std::ldexp(1.0, -23) + 1e-9 * extent;
        ASSERT_NEAR(g.positions[3 * k + a], want, tolerance) << "point " << k << " axis " << a;
        ASSERT_GE(want, c[a] - half[a] - 1e-9 * extent) << "point " << k << " lies in the box";
        ASSERT_LE(want, c[a] + half[a] + 1e-9 * extent) << "point " << k << " lies in the box";
        if (rgb) {
          ASSERT_EQ(g.rgb[3 * k + a], h.points.rgb[3 * (n.first_point + k) + a] >> colour_shift) << "point " << k;
        }
      }
    }
    const std::vector<SyntheticProperty> props = synthetic_properties(h);
    EXPECT_EQ(g.properties.size(), props.size());
    for (const SyntheticProperty& sp : props) {
      ASSERT_TRUE(g.properties.count(sp.name)) << sp.name;
      const std::vector<double>& v = g.properties.at(sp.name);
      ASSERT_EQ(v.size(), n.point_count);
      double lo = INFINITY, hi = -INFINITY;
      for (uint64_t k = 0; k < n.point_count; ++k) {
        const double x = synthetic_value(h, sp, n.first_point + k);
        lo = std::min(lo, x), hi = std::max(hi, x);
      }
      // Float relative to the tile's minimum: half an ulp of the span.
      const double tolerance = sp.exact_in_glb ? 0 : (hi - lo) * std::ldexp(1.0, -24) * 1.0001;
      for (uint64_t k = 0; k < n.point_count; ++k)
        ASSERT_NEAR(v[k], synthetic_value(h, sp, n.first_point + k), tolerance) << sp.name << " point " << k;
    }
    if (!props.empty()) {
      ++seen.feature_tiles;
      EXPECT_EQ(g.feature_label, "classification");
      ASSERT_EQ(g.feature_ids.size(), n.point_count);
      for (uint64_t k = 0; k < n.point_count; ++k)
        ASSERT_EQ(g.feature_ids[k], g.properties.at("classification")[k]) << "point " << k;
    } else {
      EXPECT_TRUE(g.feature_ids.empty());
    }
    if (n.leaf()) seen.leaf_points += g.points;
  }
  if (n.leaf()) {
    EXPECT_FALSE(t.contains("children"));
    return;
  }
  const json& children = t.at("children");
  ASSERT_EQ(children.size(), size_t(std::popcount(n.child_mask)));
  for (size_t k = 0; k < children.size(); ++k)
    v11_check_tile(h, dir, colour_shift, f, children[k], n.first_child + k, error, seen);
}

// The points' bounds in the input's coordinates, computed here.
void v11_bounds(const PointHierarchy& h, double lo[3], double hi[3]) {
  for (int a = 0; a < 3; ++a) lo[a] = INFINITY, hi[a] = -INFINITY;
  for (uint64_t p = 0; p < h.points.size(); ++p)
    for (int a = 0; a < 3; ++a) {
      const double w = h.source.offset[a] + h.source.scale[a] * double(h.points.xyz[3 * p + a]);
      lo[a] = std::min(lo[a], w), hi[a] = std::max(hi[a], w);
    }
}

// Writes `h` as 1.1 and checks all of it: returns tileset.json.
json v11_write_and_check(const PointHierarchy& h, const std::string& name, int colour_shift,
                         const io::Tiles3dOptions& o = {}) {
  const std::string dir = temp_path(name);
  io::write_3dtiles(dir, h, o);
  const json ts = read_json(dir + "/tileset.json");
  EXPECT_EQ(ts.at("asset").at("version"), "1.1");
  const json& x = ts["asset"].at("extras");
  V11Frame f;
  for (int a = 0; a < 3; ++a) f.origin[a] = x.at("localOrigin")[a], f.units[a] = x.at("unitsToMetres")[a];
  // The origin is the bounds' centre; the root's box, the bounds.
  double lo[3], hi[3];
  v11_bounds(h, lo, hi);
  const std::vector<double> box = ts.at("root").at("boundingVolume").at("box");
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(f.origin[a], (lo[a] + hi[a]) / 2, 1e-9 * std::abs(hi[a]) + 1e-9);
    EXPECT_NEAR(box[a], 0, 1e-9);
    EXPECT_NEAR(box[3 + 4 * a], (hi[a] - lo[a]) / 2 * f.units[a], 1e-9 * (hi[a] - lo[a]) * f.units[a] + 1e-12);
  }
  EXPECT_EQ(ts["root"].at("refine"), "REPLACE");
  EXPECT_EQ(ts["root"].at("transform").size(), 16u);
  std::vector<std::string> names;
  for (const SyntheticProperty& p : synthetic_properties(h)) names.push_back(p.name);
  EXPECT_EQ(x.at("properties"), json(names));
  V11Seen seen;
  v11_check_tile(h, dir, colour_shift, f, ts.at("root"), 0, ts.at("geometricError"), seen);
  EXPECT_EQ(seen.tiles, h.nodes.size());
  EXPECT_EQ(seen.leaf_points, h.points_kept) << "REPLACE: the leaves are the whole cloud";
  uint64_t files = 0;
  for (const auto& e : fs::directory_iterator(dir + "/tiles")) files += e.path().extension() == ".glb";
  EXPECT_EQ(files, seen.files) << "no tile file that the tileset does not name";
  return ts;
}

// PROJ's own transform of (x, y, z in metres) in `crs` to EPSG:4978, x east and y north.
void v11_proj(const std::string& crs, const double p[3], double out[3]) {
  PJ_CONTEXT* ctx = proj_context_create();
  PJ* raw = proj_create_crs_to_crs(ctx, crs.c_str(), "EPSG:4978", nullptr);
  PJ* op = raw ? proj_normalize_for_visualization(ctx, raw) : nullptr;
  ASSERT_NE(op, nullptr) << crs;
  const PJ_COORD r = proj_trans(op, PJ_FWD, proj_coord(p[0], p[1], p[2], 0));
  for (int a = 0; a < 3; ++a) out[a] = r.v[a];
  proj_destroy(op);
  proj_destroy(raw);
  proj_context_destroy(ctx);
}

// transform * local, and the distance from `want` perpendicular to the ellipsoid's up there.
double v11_horizontal_miss(const std::vector<double>& m, const double local[3], const double want[3]) {
  double got[3], d[3], up[3], n = 0;
  for (int k = 0; k < 3; ++k) got[k] = m[12 + k] + m[k] * local[0] + m[4 + k] * local[1] + m[8 + k] * local[2];
  for (int k = 0; k < 3; ++k) d[k] = got[k] - want[k], up[k] = want[k], n += up[k] * up[k];
  double v = 0, dd = 0;
  for (int k = 0; k < 3; ++k) v += d[k] * up[k] / std::sqrt(n), dd += d[k] * d[k];
  return std::sqrt(std::max(0.0, dd - v * v));  // the sphere's up is within 0.2 degrees of the ellipsoid's
}

TEST(Tiles3dV11, PlacedSyntheticReadsBack) {
  SyntheticCloud c;
  c.fields = true;
  const PointHierarchy h = synthetic_hierarchy(c);
  const json ts = v11_write_and_check(h, "v11placed", 8);
  const json& x = ts["asset"]["extras"];
  EXPECT_EQ(x.at("crs"), "EPSG:32633");
  EXPECT_EQ(x.at("placement"), "EPSG:4978");
  EXPECT_EQ(x.at("upAxis"), "Z");
  EXPECT_LT(x.at("placementErrorMetres").get<double>(), 0.5);
  EXPECT_EQ(x.at("skippedProperties").size(), 2u);
  EXPECT_EQ(x.at("featureIdProperty"), "classification");
  // The origin (the local frame's zero) lands where PROJ puts it.
  double origin[3], want[3];
  for (int a = 0; a < 3; ++a) origin[a] = x.at("localOrigin")[a];
  v11_proj("EPSG:32633", origin, want);
  const double zero[3] = {0, 0, 0};
  EXPECT_LT(v11_horizontal_miss(ts["root"]["transform"], zero, want), 0.01);
}

TEST(Tiles3dV11, LocalWithoutCrs) {
  SyntheticCloud c;
  c.colour = Colour::bits8, c.z_up = false, c.crs = "", c.shift = 0, c.seed = 3;
  const PointHierarchy h = synthetic_hierarchy(c);
  const json ts = v11_write_and_check(h, "v11local", 0);
  const json& x = ts["asset"]["extras"];
  EXPECT_TRUE(x.at("crs").is_null());
  EXPECT_EQ(x.at("placement"), "local");
  EXPECT_EQ(x.at("upAxis"), "Y");
  EXPECT_FALSE(x.contains("placementErrorMetres"));
  // The transform puts the points back at the input's coordinates: a translation by the origin.
  const std::vector<double> m = ts["root"]["transform"];
  const std::vector<double> want = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, x["localOrigin"][0], x["localOrigin"][1],
                                    x["localOrigin"][2], 1};
  EXPECT_EQ(m, want);
  EXPECT_EQ(x.at("unitsToMetres"), json({1.0, 1.0, 1.0}));
}

TEST(Tiles3dV11, PlainGlbAndNoColour) {
  SyntheticCloud c;
  c.colour = Colour::none, c.points = 1500, c.capacity = 64, c.fields = true;
  v11_write_and_check(synthetic_hierarchy(c), "v11plain", 0, io::Tiles3dOptions{1, "", false});
}

TEST(Tiles3dV11, RootAlone) {
  SyntheticCloud c;
  c.points = 50;
  const PointHierarchy h = synthetic_hierarchy(c);
  ASSERT_EQ(h.nodes.size(), 1u);
  v11_write_and_check(h, "v11root", 8);
}

// Feet: the local frame and every geometric error are in metres, 0.3048 of the 1.0 tileset's (feet) errors.
TEST(Tiles3dV11, GeometricErrorsInMetres) {
  SyntheticCloud c;
  c.crs = "GeoTIFF keys (EPSG:2992)";  // Oregon Lambert (ft), as the LAS reader summarizes GeoTIFF keys
  c.points = 2000;
  const PointHierarchy h = synthetic_hierarchy(c);
  const json ts = v11_write_and_check(h, "v11feet", 8);
  EXPECT_EQ(ts["asset"]["extras"].at("crs"), "EPSG:2992");
  EXPECT_EQ(ts["asset"]["extras"].at("unitsToMetres"), json({0.3048, 0.3048, 0.3048}));
  const std::string dir10 = temp_path("v10feet");
  io::write_3dtiles(dir10, h, kTiles10);
  const json ts10 = read_json(dir10 + "/tileset.json");
  EXPECT_NEAR(ts.at("geometricError").get<double>(), 0.3048 * ts10.at("geometricError").get<double>(), 1e-9);
  EXPECT_NEAR(ts["root"].at("geometricError").get<double>(), 0.3048 * ts10["root"].at("geometricError").get<double>(),
              1e-9);
  EXPECT_NEAR(ts["root"]["children"][0].at("geometricError").get<double>(),
              0.3048 * ts10["root"]["children"][0].at("geometricError").get<double>(), 1e-9);
}

TEST(Tiles3dV11, UnusableDeclaredCrsStaysLocalAndSaysWhy) {
  for (const std::string crs : {"GeoTIFF keys (user-defined CRS)", "LOCAL_CS[\"site grid\",UNIT[\"metre\",1]]"}) {
    SCOPED_TRACE(crs);
    SyntheticCloud c;
    c.crs = crs, c.points = 300;
    const json ts = v11_write_and_check(synthetic_hierarchy(c), "v11unusable", 8);
    const json& x = ts["asset"]["extras"];
    EXPECT_TRUE(x.at("crs").is_null());
    EXPECT_EQ(x.at("declaredCrs"), crs);
    EXPECT_EQ(x.at("placement"), "local");
    EXPECT_FALSE(x.at("placementNote").get<std::string>().empty());
  }
}

TEST(Tiles3dV11, CrsOptionOverridesAndMustWork) {
  SyntheticCloud c;
  c.crs = "", c.points = 400;
  const PointHierarchy h = synthetic_hierarchy(c);
  const json ts = v11_write_and_check(h, "v11override", 8, io::Tiles3dOptions{1, "EPSG:32633", true});
  EXPECT_EQ(ts["asset"]["extras"].at("placement"), "EPSG:4978");
  EXPECT_TRUE(ts["asset"]["extras"].at("declaredCrs").is_null());

  const std::string dir = temp_path("v11badcrs");
  const io::Tiles3dOptions bad_crs{1, "EPSG:999999", true}, bad_version{2, "", true};
  const std::string msg = error_message([&] { io::write_3dtiles(dir, h, bad_crs); });
  EXPECT_NE(msg.find(dir), std::string::npos) << msg;
  EXPECT_NE(msg.find("EPSG:999999"), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists(dir));
  EXPECT_NE(error_message([&] { io::write_3dtiles(dir, h, bad_version); }).find("1.2"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir));
}

TEST(Tiles3dV11, FieldsThatDoNotFitAreErrors) {
  SyntheticCloud c;
  c.fields = true, c.points = 300;
  const std::string dir = temp_path("v11badfields");
  for (int minor : {1, 0}) {
    PointHierarchy h = synthetic_hierarchy(c);
    h.source.fields.back().offset = kSyntheticRecordBytes;
    std::string msg = error_message([&] { io::write_3dtiles(dir, h, io::Tiles3dOptions{minor, "", true}); });
    EXPECT_NE(msg.find("\"Intensity\""), std::string::npos) << msg;
    EXPECT_NE(msg.find("beyond its 38-byte attribute record"), std::string::npos) << msg;
    EXPECT_NE(msg.find(dir), std::string::npos) << msg;
    h = synthetic_hierarchy(c);
    h.points.extra.pop_back();
    msg = error_message([&] { io::write_3dtiles(dir, h, io::Tiles3dOptions{minor, "", true}); });
    EXPECT_NE(msg.find("attribute records hold"), std::string::npos) << msg;
    EXPECT_FALSE(fs::exists(dir));
  }
}

// Autzen through `points build`: every tile read back, and the root transform puts the LAS header's bounding box
// centre (Oregon Lambert, international feet, heights in feet) within 1 m of where PROJ puts it.
TEST(Tiles3dV11, AutzenPlacedWhereProjPutsIt) {
  MV_SKIP_WITHOUT_SHARED_DATA("pointcloud_autzen/autzen_trim.las");
  if (all_devices().empty()) GTEST_SKIP() << "no device (see Environment.SomeDeviceIsFound, which fails then)";
  const std::string las = shared_data_file("pointcloud_autzen/autzen_trim.las");
  PointFileOptions o;
  o.input = las;
  o.output = temp_path("autzen_v11");
  o.format = PointOutput::tiles3d;
  const PointFileReport rep = build_points_file(shared_device(all_devices()[0]), o);
  const json ts = read_json(o.output + "/tileset.json");
  const json& x = ts.at("asset").at("extras");
  EXPECT_EQ(ts["asset"].at("version"), "1.1");
  EXPECT_EQ(x.at("placement"), "EPSG:4978");
  ASSERT_TRUE(x.at("crs").is_string());
  EXPECT_LT(x.at("placementErrorMetres").get<double>(), 0.5);

  // The header's bounding box (max x, min x, max y, ... at byte 179): its centre, then its corners, each as the
  // tileset places it (local frame, root transform) against PROJ (which takes a 2D CRS's heights as metres).
  const std::vector<char> b = file_bytes(las);
  ASSERT_GE(b.size(), 227u);
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) std::memcpy(&hi[k], &b[179 + 16 * k], 8), std::memcpy(&lo[k], &b[187 + 16 * k], 8);
  auto placed_miss = [&](const double p[3]) {
    double local[3], want[3];
    for (int k = 0; k < 3; ++k)
      local[k] = (p[k] - x.at("localOrigin")[k].get<double>()) * x.at("unitsToMetres")[k].get<double>();
    const double fed[3] = {p[0], p[1], p[2] * 0.3048};
    v11_proj(x.at("crs"), fed, want);
    return v11_horizontal_miss(ts.at("root").at("transform"), local, want);
  };
  const double centre[3] = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  const double miss = placed_miss(centre);
  EXPECT_LT(miss, 1.0);
  double corners = 0;
  for (int c = 0; c < 8; ++c) {
    const double p[3] = {c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]};
    corners = std::max(corners, placed_miss(p));
  }
  EXPECT_LE(corners, x["placementErrorMetres"].get<double>() + 1e-3) << "the error the tileset states";

  // Every leaf point is there, and classification is each tile's feature ID.
  uint64_t leaf_points = 0, tiles = 0, with_classification = 0;
  std::function<void(const json&)> walk = [&](const json& t) {
    ++tiles;
    const bool leaf = !t.contains("children");
    if (t.contains("content")) {
      const GlbRead g = read_glb(o.output + "/" + t["content"]["uri"].get<std::string>());
      if (leaf) leaf_points += g.points;
      with_classification += g.properties.count("classification") && g.feature_label == "classification";
    }
    for (const json& c : t.value("children", json::array())) walk(c);
  };
  walk(ts.at("root"));
  EXPECT_EQ(tiles, rep.nodes);
  EXPECT_EQ(leaf_points, rep.points_kept);
  EXPECT_GT(with_classification, 0u);
  std::printf("Autzen 1.1: %llu tiles, %llu leaf points; header centre vs PROJ %.3g m, corners %.3g m; placement "
              "error %.3g m horizontal, %.3g m vertical; properties %s\n",
              (unsigned long long)tiles, (unsigned long long)leaf_points, miss, corners,
              x["placementErrorMetres"].get<double>(), x["placementVerticalErrorMetres"].get<double>(),
              x.at("properties").dump().c_str());
}

}  // namespace
}  // namespace mv::test
