// Readers that share no code with megavox, where they are installed: loaders.gl under Node reads every tile
// (tests/js, `npm ci` by scripts/setup.sh), and headless Chromium renders the tileset with three.js and
// 3d-tiles-renderer (scripts/setup.sh --viewer). Without them each test says so in one line and passes.
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

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

TEST(Tiles3dJs, LoadersGlReadsEveryTile) {
  if (!have_node_modules("Tiles3dJs.LoadersGlReadsEveryTile", {"@loaders.gl/core", "@loaders.gl/3d-tiles"})) return;
  SyntheticCloud eight;
  eight.colour = Colour::bits8, eight.z_up = false, eight.crs = "", eight.seed = 11;
  SyntheticCloud plain;
  plain.colour = Colour::none, plain.points = 800, plain.capacity = 50;
  int k = 0;
  for (const SyntheticCloud& c : {SyntheticCloud{}, eight, plain}) {
    const PointHierarchy h = synthetic_hierarchy(c);
    const std::string dir = temp_path("js" + std::to_string(k++));
    io::write_3dtiles(dir, h);
    const Ran r = run("node " + quoted(kJs + "/check_tileset.mjs") + " " + quoted(dir) + " " +
                      std::to_string(h.points_kept));
    std::printf("%s", r.output.c_str());
    EXPECT_EQ(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("\"ok\":true"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("\"tiles\":" + std::to_string(h.nodes.size()) + ","), std::string::npos) << r.output;
  }
}

// A real cloud through `points build --format 3dtiles`, read by loaders.gl: every leaf point is there.
TEST(Tiles3dJs, LoadersGlReadsARealBuild) {
  if (!have_node_modules("Tiles3dJs.LoadersGlReadsARealBuild", {"@loaders.gl/core", "@loaders.gl/3d-tiles"})) return;
  const std::string path = shared_data_file("pointcloud_lion_takanawa/lion_takanawa.ply");
  if (path.empty()) {
    std::printf("Tiles3dJs.LoadersGlReadsARealBuild: not run: no %s\n", shared_data_path("pointcloud_lion_takanawa").c_str());
    return;
  }
  if (all_devices().empty()) return;
  PointFileOptions o;
  o.input = path;
  o.output = temp_path("lion_tiles");
  o.format = PointOutput::tiles3d;
  const PointFileReport rep = build_points_file(shared_device(all_devices()[0]), o);
  const std::string dir = o.output;
  const Ran r = run("node " + quoted(kJs + "/check_tileset.mjs") + " " + quoted(dir) + " " +
                    std::to_string(rep.points_kept));
  std::printf("%s", r.output.c_str());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("\"ok\":true"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"tiles\":" + std::to_string(rep.nodes) + ","), std::string::npos) << r.output;
}

// The screenshot stays in the test's working folder (build/tests/tiles3d_render.png) for a person to look at.
TEST(Tiles3dJs, ChromiumRendersTileset) {
  const char* env = std::getenv("CHROMIUM");
  if (!(env && *env) && !on_path("chromium") && !on_path("chromium-browser")) {
    std::printf("Tiles3dJs.ChromiumRendersTileset: not run: no Chromium (scripts/setup.sh --viewer installs it)\n");
    return;
  }
  if (!have_node_modules("Tiles3dJs.ChromiumRendersTileset", {"puppeteer-core", "three", "3d-tiles-renderer"})) return;
  const PointHierarchy h = synthetic_hierarchy({});
  const std::string dir = temp_path("render");
  io::write_3dtiles(dir, h);
  const Ran r = run("node " + quoted(kJs + "/render_tileset.mjs") + " " + quoted(dir) + " tiles3d_render.png");
  std::printf("%s", r.output.c_str());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("\"ok\":true"), std::string::npos) << r.output;
  // And a real cloud through `points build --format 3dtiles`, where the shared data has one.
  const std::string lion = shared_data_file("pointcloud_lion_takanawa/lion_takanawa.ply");
  if (lion.empty() || all_devices().empty()) {
    std::printf("Tiles3dJs.ChromiumRendersTileset: the real cloud not run: no %s\n",
                shared_data_path("pointcloud_lion_takanawa").c_str());
    return;
  }
  PointFileOptions o;
  o.input = lion;
  o.output = temp_path("lion_render");
  o.format = PointOutput::tiles3d;
  build_points_file(shared_device(all_devices()[0]), o);
  const std::string real_dir = o.output;
  const Ran real = run("node " + quoted(kJs + "/render_tileset.mjs") + " " + quoted(real_dir) + " tiles3d_render_lion.png");
  std::printf("%s", real.output.c_str());
  EXPECT_EQ(real.status, 0) << real.output;
  EXPECT_NE(real.output.find("\"ok\":true"), std::string::npos) << real.output;
}

}  // namespace
}  // namespace mv::test
