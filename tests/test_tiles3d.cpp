// 3D Tiles 1.0 output of point hierarchies: every .pnts tile read back by hand (tiles3d_read.h) against the
// hierarchy it came from, batch tables included; failures leave the target as it was (for either version).
// 3D Tiles 1.1 (glb tiles, placement on the globe): test_tiles3d_v11.cpp.
#include <signal.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "io/tiles3d_writer.h"
#include "test_support.h"
#include "tiles3d_fixture.h"
#include "tiles3d_read.h"

namespace mv::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;



double world(const PointHierarchy& h, uint64_t point, int a) {
  return h.source.offset[a] + h.source.scale[a] * double(h.points.xyz[3 * point + a]);
}

// What the walk over the tileset saw.
struct Seen {
  uint64_t leaf_points = 0, tiles = 0, files = 0;
  std::set<uint32_t> leaf_levels;
};

// Tile `t` against node `i`: its box, error, content and children, then its children in turn.
void check_tile(const PointHierarchy& h, const std::string& dir, int colour_shift, const json& t, size_t i,
                double parent_error, const std::vector<double>* parent_box, Seen& seen) {
  const PointNode& n = h.nodes[i];
  SCOPED_TRACE("tile " + tile_name(n.code, n.level));
  ++seen.tiles;
  const double error = t.at("geometricError");
  expect_error_falls(n, error, parent_error);

  const std::vector<double> box = t.at("boundingVolume").at("box");
  ASSERT_EQ(box.size(), 12u);
  double c[3], half[3];
  for (int a = 0; a < 3; ++a) {
    c[a] = box[a];
    half[a] = box[3 + 4 * a];
    EXPECT_GT(half[a], 0.0);
    for (int b = 0; b < 3; ++b)
      if (b != a) {
        EXPECT_EQ(box[3 + 3 * a + b], 0.0) << "the box is axis-aligned";
      }
  }
  EXPECT_NEAR(half[0] / std::abs(h.source.scale[0]), std::ldexp(1.0, int(20 + h.shift - n.level)), 1e-6);
  if (parent_box) {
    for (int a = 0; a < 3; ++a) {
      const double pc = (*parent_box)[a], ph = (*parent_box)[3 + 4 * a];
      EXPECT_EQ(half[a], ph / 2) << "a child's cube is half its parent's";
      EXPECT_GE(c[a] - half[a], pc - ph - 1e-9 * ph);
      EXPECT_LE(c[a] + half[a], pc + ph + 1e-9 * ph);
    }
  }

  if (n.point_count == 0) {
    EXPECT_FALSE(t.contains("content"));
  } else {
    const std::string uri = t.at("content").at("uri");
    EXPECT_EQ(uri, "tiles/" + tile_name(n.code, n.level) + ".pnts");
    const PntsRead p = read_pnts(dir + "/" + uri);
    ++seen.files;
    EXPECT_TRUE(p.magic_ok);
    EXPECT_EQ(p.version, 1u);
    EXPECT_EQ(p.byte_length, p.file_size);
    EXPECT_EQ(p.byte_length, 28u + p.ft_json + p.ft_bin + p.bt_json + p.bt_bin);
    EXPECT_EQ((28 + p.ft_json) % 8, 0u) << "the binary body starts on 8 bytes";
    EXPECT_EQ(p.ft_bin % 8, 0u) << "the batch table starts on 8 bytes";
    EXPECT_EQ(p.bt_json % 8, 0u) << "the batch table's binary body starts on 8 bytes";
    EXPECT_EQ(p.byte_length % 8, 0u) << "the tile ends on 8 bytes";
    const std::vector<SyntheticProperty> props = synthetic_properties(h);
    if (props.empty()) {
      EXPECT_EQ(p.bt_json, 0u);
      EXPECT_EQ(p.bt_bin, 0u);
    }
    EXPECT_EQ(p.properties.size(), props.size());
    EXPECT_FALSE(p.feature_table.contains("BATCH_ID")) << "per-point properties: the batch table is POINTS_LENGTH long";
    for (const SyntheticProperty& sp : props) {
      ASSERT_TRUE(p.properties.count(sp.name)) << sp.name;
      const std::vector<double>& v = p.properties.at(sp.name);
      ASSERT_EQ(v.size(), n.point_count) << sp.name;
      for (uint64_t k = 0; k < n.point_count; ++k)
        ASSERT_EQ(v[k], synthetic_value(h, sp, n.first_point + k)) << sp.name << " point " << k;
    }
    const json& ft = p.feature_table;
    EXPECT_EQ(ft.at("POINTS_LENGTH").get<uint64_t>(), n.point_count);
    EXPECT_EQ(ft.at("POSITION").at("byteOffset").get<uint64_t>(), 0u);
    const bool rgb = h.source.attributes & kPointRgb;
    EXPECT_EQ(ft.contains("RGB"), rgb);
    if (rgb) {
      EXPECT_EQ(ft["RGB"]["byteOffset"].get<uint64_t>(), 12ull * n.point_count);
    }
    EXPECT_LT(p.ft_bin - (12ull + 3 * rgb) * n.point_count, 8u) << "padding only";
    const std::vector<double> rtc = ft.at("RTC_CENTER");
    ASSERT_EQ(rtc.size(), 3u);
    ASSERT_EQ(p.positions.size(), 3ull * n.point_count);
    const double tolerance = std::max({half[0], half[1], half[2]}) * std::ldexp(1.0, -22);
    for (uint64_t k = 0; k < n.point_count; ++k) {
      const uint64_t at = n.first_point + k;
      for (int a = 0; a < 3; ++a) {
        EXPECT_EQ(rtc[a], c[a]) << "RTC_CENTER is the box centre";
        const double w = world(h, at, a);
        ASSERT_NEAR(rtc[a] + p.positions[3 * k + a], w, tolerance) << "point " << k << " axis " << a;
        ASSERT_GE(w, c[a] - half[a]) << "point " << k << " lies in the box";
        ASSERT_LE(w, c[a] + half[a]) << "point " << k << " lies in the box";
        if (rgb) {
          ASSERT_EQ(p.rgb[3 * k + a], h.points.rgb[3 * at + a] >> colour_shift) << "point " << k;
        }
      }
    }
    if (n.leaf()) seen.leaf_points += ft["POINTS_LENGTH"].get<uint64_t>();
  }
  if (n.leaf()) {
    seen.leaf_levels.insert(n.level);
    EXPECT_FALSE(t.contains("children"));
    return;
  }
  const json& children = t.at("children");
  ASSERT_EQ(children.size(), size_t(__builtin_popcount(n.child_mask)));
  for (size_t k = 0; k < children.size(); ++k)
    check_tile(h, dir, colour_shift, children[k], n.first_child + k, error, &box, seen);
}

// Writes `h` to a fresh folder and checks all of it; returns what the walk saw.
Seen write_and_check(const PointHierarchy& h, const std::string& name, int colour_shift) {
  const std::string dir = temp_path(name);
  io::write_3dtiles(dir, h, kTiles10);
  const json ts = read_json(dir + "/tileset.json");
  EXPECT_EQ(ts.at("asset").at("version"), "1.0");
  const json& extras = ts["asset"].at("extras");
  if (h.source.crs.empty()) {
    EXPECT_TRUE(extras.at("crs").is_null());
  } else {
    EXPECT_EQ(extras.at("crs"), h.source.crs);
  }
  EXPECT_EQ(extras.at("upAxis"), h.source.z_up ? "Z" : "Y");
  std::vector<std::string> names;
  for (const SyntheticProperty& p : synthetic_properties(h)) names.push_back(p.name);
  EXPECT_EQ(extras.at("properties"), json(names));
  std::vector<std::string> skipped;
  for (const json& s : extras.value("skippedProperties", json::array())) {
    skipped.push_back(s.at("name"));
    EXPECT_FALSE(s.at("reason").get<std::string>().empty());
  }
  EXPECT_EQ(skipped, synthetic_skipped(h));
  const json& root = ts.at("root");
  EXPECT_EQ(root.at("refine"), "REPLACE");
  Seen seen;
  check_tile(h, dir, colour_shift, root, 0, ts.at("geometricError"), nullptr, seen);
  EXPECT_EQ(seen.tiles, h.nodes.size());
  EXPECT_EQ(seen.leaf_points, h.points_kept) << "REPLACE: the leaves are the whole cloud";
  uint64_t files = 0;
  for (const auto& e : fs::directory_iterator(dir + "/tiles")) files += e.path().extension() == ".pnts";
  EXPECT_EQ(files, seen.files) << "no tile file that the tileset does not name";
  return seen;
}

TEST(Tiles3d, SixteenBitColourTilesetReadsBack) {
  const PointHierarchy h = synthetic_hierarchy({});
  ASSERT_GT(h.nodes.size(), 20u);
  const Seen seen = write_and_check(h, "rgb16", 8);
  EXPECT_GE(seen.leaf_levels.size(), 3u) << "the fixture has leaves at several levels";
}

TEST(Tiles3d, EightBitColourYUpNoCrs) {
  SyntheticCloud c;
  c.colour = Colour::bits8, c.z_up = false, c.crs = "", c.shift = 0, c.seed = 3;
  write_and_check(synthetic_hierarchy(c), "rgb8", 0);
}

TEST(Tiles3d, FieldsGoInTheBatchTable) {
  SyntheticCloud c;
  c.fields = true, c.points = 3000, c.seed = 5;
  const PointHierarchy h = synthetic_hierarchy(c);
  write_and_check(h, "fields10", 8);
}

TEST(Tiles3d, NoColour) {
  SyntheticCloud c;
  c.colour = Colour::none, c.points = 1500, c.capacity = 64;
  write_and_check(synthetic_hierarchy(c), "plain", 0);
}

TEST(Tiles3d, RootAlone) {
  SyntheticCloud c;
  c.points = 50;
  const PointHierarchy h = synthetic_hierarchy(c);
  ASSERT_EQ(h.nodes.size(), 1u);
  write_and_check(h, "root", 8);
}

// Only DIR is left in `parent`: no temporary or old folders beside it.
void expect_only(const std::string& parent, const std::set<std::string>& names) {
  std::set<std::string> found;
  for (const auto& e : fs::directory_iterator(parent)) found.insert(e.path().filename().string());
  EXPECT_EQ(found, names);
}

TEST(Tiles3d, ReplacesAnEarlierTileset) {
  const std::string parent = temp_path("again");
  fs::create_directories(parent);
  const std::string dir = parent + "/tiles3d";
  io::write_3dtiles(dir, synthetic_hierarchy({}));
  SyntheticCloud c;
  c.points = 50;
  io::write_3dtiles(dir, synthetic_hierarchy(c));
  expect_only(parent, {"tiles3d"});
  expect_only(dir + "/tiles", {"r.glb"});
  io::write_3dtiles(dir + "/", synthetic_hierarchy(c), kTiles10);  // a trailing slash: the same folder
  expect_only(dir + "/tiles", {"r.pnts"});
  expect_only(parent, {"tiles3d"});
}

TEST(Tiles3d, UnwritablePlacesGiveErrorsAndLeaveNothing) {
  const PointHierarchy h = synthetic_hierarchy({});
  std::string msg = error_message([&] { io::write_3dtiles("/proc/megavox-tiles", h); });
  EXPECT_NE(msg.find("/proc/megavox-tiles"), std::string::npos) << msg;
  EXPECT_FALSE(fs::exists("/proc/megavox-tiles"));

  const std::string parent = temp_path("file-parent");
  fs::create_directories(parent);
  std::ofstream(parent + "/a-file") << "x";
  msg = error_message([&] { io::write_3dtiles(parent + "/a-file/out", h); });
  EXPECT_NE(msg.find(parent + "/a-file/out"), std::string::npos) << msg;
  expect_only(parent, {"a-file"});
}

// A write that fails part-way (files may not grow past 4 KiB, so the first large tile fails): the temporary
// folder goes, the earlier tileset stays.
TEST(Tiles3d, FailurePartWayLeavesTheEarlierTileset) {
  const std::string parent = temp_path("partway");
  fs::create_directories(parent);
  const std::string dir = parent + "/out";
  SyntheticCloud small;
  small.points = 50;
  io::write_3dtiles(dir, synthetic_hierarchy(small));
  const std::vector<char> before = file_bytes(dir + "/tileset.json");

  const PointHierarchy big = synthetic_hierarchy({});
  ::signal(SIGXFSZ, SIG_IGN);  // a write past the limit then fails with EFBIG instead of ending the process
  rlimit old{};
  ::getrlimit(RLIMIT_FSIZE, &old);
  rlimit tight = old;
  tight.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &tight), 0);
  const std::string msg = error_message([&] { io::write_3dtiles(dir, big); });
  ::setrlimit(RLIMIT_FSIZE, &old);
  EXPECT_NE(msg.find("cannot write '" + dir + "'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("File too large"), std::string::npos) << msg;
  expect_only(parent, {"out"});
  EXPECT_EQ(file_bytes(dir + "/tileset.json"), before);
}

TEST(Tiles3d, LeavesOtherFoldersAndFilesAlone) {
  const std::string parent = temp_path("others");
  fs::create_directories(parent + "/photos");
  std::ofstream(parent + "/photos/cat.jpg") << "meow";
  std::ofstream(parent + "/notes.txt") << "x";
  const PointHierarchy h = synthetic_hierarchy({});
  std::string msg = error_message([&] { io::write_3dtiles(parent + "/photos", h); });
  EXPECT_NE(msg.find("not replacing it"), std::string::npos) << msg;
  msg = error_message([&] { io::write_3dtiles(parent + "/notes.txt", h); });
  EXPECT_NE(msg.find("is not a folder"), std::string::npos) << msg;
  expect_only(parent, {"photos", "notes.txt"});
  expect_only(parent + "/photos", {"cat.jpg"});
}

TEST(Tiles3d, InconsistentHierarchiesAreErrors) {
  const std::string dir = temp_path("bad");
  PointHierarchy h = synthetic_hierarchy({});
  ++h.points_kept;
  EXPECT_NE(error_message([&] { io::write_3dtiles(dir, h); }).find("leaves hold"), std::string::npos);
  h = synthetic_hierarchy({});
  h.nodes[0].first_child = 2;
  EXPECT_NE(error_message([&] { io::write_3dtiles(dir, h); }).find("breadth-first"), std::string::npos);
  h = synthetic_hierarchy({});
  h.nodes.back().point_count = uint32_t(h.points.size());
  EXPECT_NE(error_message([&] { io::write_3dtiles(dir, h); }).find("beyond"), std::string::npos);
  h = synthetic_hierarchy({});
  h.points.rgb.pop_back();
  EXPECT_NE(error_message([&] { io::write_3dtiles(dir, h); }).find("rgb column"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir));
}

}  // namespace
}  // namespace mv::test
