// Readers that share no code with megavox, where they are installed: loaders.gl under Node reads every tile of
// 3D Tiles 1.1 and 1.0 tilesets (tests/js, `npm ci` by scripts/setup.sh), and headless Chromium renders them
// with three.js and 3d-tiles-renderer and loads them with CesiumJS (scripts/setup.sh --viewer). Without them
// each test says so in one line and passes.
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <set>

#include "io/tiles3d_writer.h"
#include "megavox/point_build.h"
#include "test_support.h"
#include "tiles3d_fixture.h"

namespace mv::test {
namespace {

namespace fs = std::filesystem;

const std::string kJs = std::string(MEGAVOX_SOURCE_DIR) + "/tests/js";

bool on_path(const std::string& program) {
  return std::system(("command -v " + program + " >/dev/null 2>&1").c_str()) == 0;
}

struct Ran {
  int status = -1;
  std::string output;
};

Ran run(const std::string& command) {
  Ran r;
  std::FILE* p = ::popen((command + " 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  for (size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) r.output.append(buf, n);
  const int st = ::pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

std::string quoted(const std::string& s) { return "'" + s + "'"; }

bool have_node_modules(const char* test, const std::vector<std::string>& packages) {
  for (const std::string& p : packages) {
    if (!fs::exists(kJs + "/node_modules/" + p) || !on_path("node")) {
      std::printf("%s: not run: no node or tests/js/node_modules/%s (scripts/setup.sh installs them with npm ci)\n",
                  test, p.c_str());
      return false;
    }
  }
  return true;
}

bool have_chromium(const char* test) {
  const char* env = std::getenv("CHROMIUM");
  if ((env && *env) || on_path("chromium") || on_path("chromium-browser")) return true;
  std::printf("%s: not run: no Chromium (scripts/setup.sh --viewer installs it)\n", test);
  return false;
}

// check_tileset.mjs on DIR: it must load every tile, count `tiles` of them and `leaf_points` at the leaves.
Ran check_tileset(const std::string& dir, uint64_t leaf_points, uint64_t tiles, const char* version) {
  const Ran r = run("node " + quoted(kJs + "/check_tileset.mjs") + " " + quoted(dir) + " " +
                    std::to_string(leaf_points) + " " + version);
  std::printf("%s", r.output.c_str());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("\"ok\":true"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"tiles\":" + std::to_string(tiles) + ","), std::string::npos) << r.output;
  return r;
}

// Every synthetic cloud as 3D Tiles 1.1 (glb, meshopt, placed or local) and 1.0 (.pnts, batch tables).
TEST(Tiles3dJs, LoadersGlReadsEveryTile) {
  if (!have_node_modules("Tiles3dJs.LoadersGlReadsEveryTile", {"@loaders.gl/core", "@loaders.gl/3d-tiles"})) return;
  SyntheticCloud eight;
  eight.colour = Colour::bits8, eight.z_up = false, eight.crs = "", eight.seed = 11;
  SyntheticCloud plain;
  plain.colour = Colour::none, plain.points = 800, plain.capacity = 50;
  SyntheticCloud fields;
  fields.fields = true, fields.points = 3000;
  int k = 0;
  for (const SyntheticCloud& c : {SyntheticCloud{}, eight, plain, fields}) {
    const PointHierarchy h = synthetic_hierarchy(c);
    for (int minor : {1, 0}) {
      const std::string dir = temp_path("js" + std::to_string(k++));
      io::write_3dtiles(dir, h, io::Tiles3dOptions{minor, "", true});
      const Ran r = check_tileset(dir, h.points_kept, h.nodes.size(), minor ? "1.1" : "1.0");
      if (c.fields) {
        EXPECT_NE(r.output.find("\"classification\""), std::string::npos) << "a property loaders.gl read: " << r.output;
        EXPECT_NE(r.output.find("\"gps_time\""), std::string::npos) << r.output;
      }
      if (c.fields && minor) {
        EXPECT_NE(r.output.find("\"featureIdTiles\":" + std::to_string(h.nodes.size())), std::string::npos)
            << "every tile's classification is its feature IDs: " << r.output;
      }
    }
  }
}

// Real clouds through `points build --format 3dtiles` (1.1, and lion as 1.0 too), read by loaders.gl: every leaf
// point is there; Autzen's LAS fields arrive as properties, placed on the globe.
TEST(Tiles3dJs, LoadersGlReadsARealBuild) {
  if (!have_node_modules("Tiles3dJs.LoadersGlReadsARealBuild", {"@loaders.gl/core", "@loaders.gl/3d-tiles"})) return;
  if (all_devices().empty()) return;
  struct Real {
    const char* file;
    int minor;
  };
  int k = 0;
  for (const Real c : {Real{"pointcloud_lion_takanawa/lion_takanawa.ply", 1},
                       Real{"pointcloud_lion_takanawa/lion_takanawa.ply", 0},
                       Real{"pointcloud_autzen/autzen_trim.las", 1}}) {
    const std::string path = shared_data_file(c.file);
    if (path.empty()) {
      std::printf("Tiles3dJs.LoadersGlReadsARealBuild: not run: no %s\n", shared_data_path(c.file).c_str());
      continue;
    }
    PointFileOptions o;
    o.input = path;
    o.output = temp_path("real_tiles" + std::to_string(k++));
    o.format = PointOutput::tiles3d;
    o.tiles_minor_version = c.minor;
    const PointFileReport rep = build_points_file(shared_device(all_devices()[0]), o);
    const Ran r = check_tileset(o.output, rep.points_kept, rep.nodes, c.minor ? "1.1" : "1.0");
    if (std::string(c.file).ends_with(".las")) {
      EXPECT_NE(r.output.find("\"placement\":\"EPSG:4978\""), std::string::npos) << r.output;
      EXPECT_NE(r.output.find("\"classification\""), std::string::npos) << r.output;
    }
  }
}

// The screenshot stays in the test's working folder (build/tests/tiles3d_render.png) for a person to look at.
TEST(Tiles3dJs, ChromiumRendersTileset) {
  if (!have_chromium("Tiles3dJs.ChromiumRendersTileset")) return;
  if (!have_node_modules("Tiles3dJs.ChromiumRendersTileset", {"puppeteer-core", "three", "3d-tiles-renderer"})) return;
  // A synthetic cloud placed on the globe as 1.1 (glb through three's MeshoptDecoder), and as 1.0.
  const PointHierarchy h = synthetic_hierarchy({});
  for (int minor : {1, 0}) {
    const std::string dir = temp_path("render" + std::to_string(minor));
    io::write_3dtiles(dir, h, io::Tiles3dOptions{minor, "", true});
    const std::string png = minor ? "tiles3d_render.png" : "tiles3d_render_10.png";
    const Ran r = run("node " + quoted(kJs + "/render_tileset.mjs") + " " + quoted(dir) + " " + png);
    std::printf("%s", r.output.c_str());
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"ok\":true"), std::string::npos) << r.output;
  }
  // And real clouds through `points build --format 3dtiles` (1.1): lion (local) and Autzen (placed on the globe).
  for (const char* file : {"pointcloud_lion_takanawa/lion_takanawa.ply", "pointcloud_autzen/autzen_trim.las"}) {
    const std::string path = shared_data_file(file);
    if (path.empty() || all_devices().empty()) {
      std::printf("Tiles3dJs.ChromiumRendersTileset: the real cloud not run: no %s or no device\n",
                  shared_data_path(file).c_str());
      continue;
    }
    const std::string name = std::string(file).ends_with(".las") ? "autzen" : "lion";
    PointFileOptions o;
    o.input = path;
    o.output = temp_path("render_" + name);
    o.format = PointOutput::tiles3d;
    build_points_file(shared_device(all_devices()[0]), o);
    const std::string dir = o.output;  // const: std::quoted's non-const overload would win the call below
    const Ran real = run("node " + quoted(kJs + "/render_tileset.mjs") + " " + quoted(dir) + " tiles3d_render_" + name +
                         ".png");
    std::printf("%s", real.output.c_str());
    EXPECT_EQ(real.status, 0) << real.output;
    EXPECT_NE(real.output.find("\"ok\":true"), std::string::npos) << real.output;
  }
}

// cesium_tileset.mjs on DIR with ARGS: CesiumJS loads every tile without an error or a request off the machine.
void cesium_loads(const std::string& dir, const std::string& args) {
  const Ran r = run("node " + quoted(kJs + "/cesium_tileset.mjs") + " " + quoted(dir) + " " + args);
  std::printf("%s", r.output.c_str());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("\"ok\":true"), std::string::npos) << r.output;
}

// CesiumJS (tests/js/cesium_tileset.mjs): a synthetic cloud with LAS-like fields as 1.1 (glb: meshopt, quantized,
// classification as feature IDs and a property attribute) and as 1.0 (.pnts, batch table); the leaves hold every
// point, and the classifications Cesium draws from the tiles' metadata are the cloud's. Then Autzen (LAS 1.2, classes
// 1 and 2) as both, its 1.1 placed in Eugene, Oregon.
TEST(Tiles3dJs, CesiumLoadsTileset) {
  if (!have_chromium("Tiles3dJs.CesiumLoadsTileset")) return;
  if (!have_node_modules("Tiles3dJs.CesiumLoadsTileset", {"puppeteer-core", "@cesium/engine", "esbuild"})) return;
  SyntheticCloud c;
  c.fields = true, c.points = 3000;
  const PointHierarchy h = synthetic_hierarchy(c);
  std::set<int> classes;
  for (const SyntheticProperty& p : synthetic_properties(h)) {
    if (p.name != "classification") continue;
    for (const PointNode& n : h.nodes)
      for (uint64_t k = 0; k < n.point_count; ++k) classes.insert(int(synthetic_value(h, p, n.first_point + k)));
  }
  ASSERT_FALSE(classes.empty());
  std::string list;
  for (int k : classes) list += (list.empty() ? "" : ",") + std::to_string(k);
  for (int minor : {1, 0}) {
    const std::string dir = temp_path("cesium" + std::to_string(minor));
    io::write_3dtiles(dir, h, io::Tiles3dOptions{minor, "", true});
    cesium_loads(dir, "--points " + std::to_string(h.points_kept) + " --classes " + list);
  }
  const char* autzen = "pointcloud_autzen/autzen_trim.las";
  if (shared_data_file(autzen).empty() || all_devices().empty()) {
    std::printf("Tiles3dJs.CesiumLoadsTileset: Autzen not run: no %s or no device\n", shared_data_path(autzen).c_str());
    return;
  }
  for (int minor : {1, 0}) {
    PointFileOptions o;
    o.input = shared_data_file(autzen);
    o.output = temp_path("cesium_autzen" + std::to_string(minor));
    o.format = PointOutput::tiles3d;
    o.tiles_minor_version = minor;
    const PointFileReport rep = build_points_file(shared_device(all_devices()[0]), o);
    // 1.0 stays in the input's coordinates (Oregon Lambert feet), which Cesium reads as ECEF: nowhere to check.
    cesium_loads(o.output, "--points " + std::to_string(rep.points_kept) + " --classes 1,2" +
                               (minor ? " --near 44.05,-123.07" : ""));
  }
}

}  // namespace
}  // namespace mv::test
