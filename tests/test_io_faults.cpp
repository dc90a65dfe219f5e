// Injected I/O faults (io/file_ops.h) at every read, write and rename of build, export, import, render and
// points build: each operation is run once per I/O call of a fault kind, that call failing (ENOSPC on a write,
// EIO on a read, a read cut short where the file then ends, a failing rename). Every run must either throw
// mv::Error with a clear message, leaving the folder as it was (no output, no temporary file) and no file
// descriptor open, or, when the fault fell where a reader can do without it, write exactly the fault-free
// output. Memory leaks on these paths are ASan's part (scripts/test.sh --sanitize).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <cmath>
#include <functional>
#include <map>
#include <regex>
#include <set>

#include "io/file_ops.h"
#include "io/vdb_source.h"
#include "megavox/build.h"
#include "megavox/interop.h"
#include "megavox/mvx.h"
#include "megavox/point_build.h"
#include "megavox/render.h"
#include "megavox/trace.h"
#include "option_words.h"
#include "test_support.h"

namespace mv::test {
namespace {

namespace fs = std::filesystem;
using io::faults::Kind;

class IoFaults : public ::testing::TestWithParam<DeviceInfo> {
 protected:
  Device& dev() { return shared_device(GetParam()); }
  void TearDown() override { io::faults::disarm(); }
};

size_t open_fds() {
  size_t n = 0;
  for (const auto& e : fs::directory_iterator("/proc/self/fd")) n += e.path().filename() != "." ? 1 : 0;
  return n;
}

// Every file and folder under `dir`, by relative path.
std::set<std::string> listing(const std::string& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) out.insert(fs::relative(e.path(), dir).string());
  return out;
}

using Contents = std::map<std::string, std::vector<char>>;

// The output's bytes (a file, or a folder's files by name).
Contents output_bytes(const std::string& path) {
  std::map<std::string, std::vector<char>> out;
  if (fs::is_directory(path)) {
    for (const auto& e : fs::recursive_directory_iterator(path))
      if (e.is_regular_file()) out[fs::relative(e.path(), path).string()] = file_bytes(e.path().string());
  } else {
    out[""] = file_bytes(path);
  }
  return out;
}

const char* kind_name(Kind k) {
  switch (k) {
    case Kind::kNoSpace: return "ENOSPC on write";
    case Kind::kReadError: return "EIO on read";
    case Kind::kShortRead: return "short read";
    case Kind::kRenameFails: return "failing rename";
    case Kind::kMappedRead: return "EIO on a mapped page read";
  }
  return "?";
}

// What a clear message of each fault says.
const std::regex& expected_words(Kind k) {
  static const std::regex no_space("No space left on device"), eio("Input/output error"),
      short_read("truncated|ended|end of|short|complete|bytes of|past the end|fewer|not a");  // cut to a few bytes, a
                                                                                    // file is not of its kind
  return k == Kind::kNoSpace ? no_space : k == Kind::kShortRead ? short_read : eio;
}

// A .vdb's voxels (OpenVDB writes a fresh UUID into every file).
Contents vdb_voxels(const std::string& path) {
  const std::vector<uint64_t> keys = io::read_vdb(path, "", 0).keys;
  const char* p = reinterpret_cast<const char*>(keys.data());
  return {{"", std::vector<char>(p, p + keys.size() * sizeof(uint64_t))}};
}

// Runs `op` (which writes `output` inside `dir`) once fault-free for the reference output, then once per I/O
// call of each fault kind with that call failing; returns how many faults were injected in all.
uint64_t sweep(const std::string& dir, const std::string& output, const std::function<void()>& op,
               const std::function<Contents(const std::string&)>& output_of = output_bytes) {
  op();
  const auto reference = output_of(output);
  fs::remove_all(output);
  const std::set<std::string> before = listing(dir);
  const size_t fds = open_fds();
  uint64_t injected = 0;
  for (Kind kind : {Kind::kNoSpace, Kind::kReadError, Kind::kShortRead, Kind::kRenameFails}) {
    for (uint64_t nth = 0;; ++nth) {
      SCOPED_TRACE(std::string(kind_name(kind)) + " at I/O call " + std::to_string(nth));
      io::faults::arm(kind, nth);
      std::string message;
      try {
        op();
      } catch (const Error& e) {
        message = e.what();
      }
      const bool fired = io::faults::fired();
      io::faults::disarm();
      if (!fired) {  // past the last call of this kind: the run was whole
        EXPECT_TRUE(message.empty()) << message;
        EXPECT_EQ(output_of(output), reference);
        fs::remove_all(output);
        break;
      }
      ++injected;
      std::printf("  %s at I/O call %llu: %s\n", kind_name(kind), (unsigned long long)nth,
                  message.empty() ? "(survived; the output is exact)" : message.c_str());
      if (message.empty()) {  // the fault was survivable: then the output must be exactly right
        EXPECT_EQ(output_of(output), reference);
        fs::remove_all(output);
      } else {
        EXPECT_TRUE(std::regex_search(message, expected_words(kind))) << message;
      }
      EXPECT_EQ(listing(dir), before) << "after: " << message;
      EXPECT_EQ(open_fds(), fds) << "after: " << message;
      if (::testing::Test::HasFailure()) return injected;
    }
  }
  return injected;
}

// A closed bumpy sphere (a few thousand triangles), as a binary PLY or, with `obj`, a Wavefront OBJ (assimp's).
std::string sphere_mesh(const std::string& dir, bool obj = false) {
  std::vector<float> pos;
  std::vector<uint32_t> idx;
  const int rings = 16, segs = 32;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s < segs; ++s) {
      const double th = M_PI * r / rings, ph = 2 * M_PI * s / segs, rad = 1.0 + 0.1 * std::sin(4 * th);
      pos.insert(pos.end(), {float(rad * std::sin(th) * std::cos(ph)), float(rad * std::cos(th)),
                             float(rad * std::sin(th) * std::sin(ph))});
    }
  for (uint32_t r = 0; r < rings; ++r)
    for (uint32_t s = 0; s < segs; ++s) {
      const uint32_t a = r * segs + s, b = r * segs + (s + 1) % segs, c = a + segs, d = b + segs;
      idx.insert(idx.end(), {a, c, b, b, c, d});
    }
  const std::string path = dir + (obj ? "/sphere.obj" : "/sphere.ply");
  if (obj) {
    write_obj(path, pos, idx);
  } else {
    write_ply(path, pos, idx);
  }
  return path;
}

// A cloud of 3000 points as a binary PLY.
std::string point_cloud(const std::string& dir) {
  const std::string path = dir + "/cloud.ply";
  std::FILE* f = std::fopen(path.c_str(), "wb");
  const int n = 3000;
  std::fprintf(f, "ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
                  "property float z\nend_header\n", n);
  for (int i = 0; i < n; ++i) {
    const float p[3] = {float(i % 17) * 0.5f, float(i % 23) * 0.25f, float(i % 29)};
    std::fwrite(p, sizeof p, 1, f);
  }
  std::fclose(f);
  return path;
}

std::string scratch(const std::string& name) {
  const std::string dir = temp_path(name);
  fs::create_directories(dir);
  return dir;
}

BuildOptions mesh_build(const std::string& dir) {
  BuildOptions o;
  o.input = sphere_mesh(dir);
  o.output = dir + "/out.mvx";
  o.resolution = 32;
  return o;
}

TEST_P(IoFaults, Build) {
  const std::string dir = scratch("faults_build");
  const BuildOptions o = mesh_build(dir);
  EXPECT_GT(sweep(dir, o.output, [&] { build_mvx(dev(), o); }), 4u);
}

// The mesh read by assimp, whose file access goes through the file layer (io/assimp_files.h).
TEST_P(IoFaults, BuildFromObj) {
  const std::string dir = scratch("faults_obj");
  BuildOptions o = mesh_build(dir);
  o.input = sphere_mesh(dir, /*obj=*/true);
  EXPECT_GT(sweep(dir, o.output, [&] { build_mvx(dev(), o); }), 4u);
}

// A .vdb read by OpenVDB, from a stream over the file layer (io/file_streambuf.h).
TEST_P(IoFaults, BuildFromVdb) {
  const std::string dir = scratch("faults_vdb");
  const BuildOptions b = mesh_build(dir);
  build_mvx(dev(), b);
  BuildOptions o;
  o.input = dir + "/in.vdb";
  o.output = dir + "/from_vdb.mvx";
  export_mvx(dev(), ExportOptions{b.output, o.input, ExportFormat::vdb});
  EXPECT_GT(sweep(dir, o.output, [&] { build_mvx(dev(), o); }), 4u);
}

// Out of core with the triangles spilled to a scratch file (its writes and reads-back fail too).
TEST_P(IoFaults, BuildOutOfCoreSpilling) {
  const std::string dir = scratch("faults_ooc");
  BuildOptions o = mesh_build(dir);
  o.cube = 16;
  o.memory = 128 << 10;
  EXPECT_GT(sweep(dir, o.output, [&] { EXPECT_GT(build_mvx(dev(), o).spilled_bytes, 0u); }), 8u);
}

TEST_P(IoFaults, ExportAndImport) {
  const std::string dir = scratch("faults_interop");
  BuildOptions b = mesh_build(dir);
  b.encoding = Encoding::ssvdag;
  build_mvx(dev(), b);
  for (const char* format : {"symvox-ssvdag", "symvox-svdag", "vdb"}) {
    SCOPED_TRACE(format);
    const ExportOptions e{b.output, dir + "/out." + std::string(format), parse_export_format(format)};
    const bool vdb = e.format == ExportFormat::vdb;
    EXPECT_GT(sweep(dir, e.output, [&] { export_mvx(dev(), e); }, vdb ? vdb_voxels : output_bytes), 2u);
  }
  const ExportOptions e{b.output, dir + "/in.ssvdag", ExportFormat::symvox_ssvdag};
  export_mvx(dev(), e);
  ImportOptions i;
  i.input = e.output;
  i.output = dir + "/imported.mvx";
  EXPECT_GT(sweep(dir, i.output, [&] { import_symvox(dev(), i); }), 3u);
}

TEST_P(IoFaults, Render) {
  const std::string dir = scratch("faults_render");
  BuildOptions b = mesh_build(dir);
  build_mvx(dev(), b);
  RenderOptions r;
  r.width = 48;
  r.height = 32;
  r.ao_samples = 2;
  const std::string png = dir + "/out.png";
  EXPECT_GT(sweep(dir, png, [&] {
              const MvxFile file = read_mvx(b.output);
              Tracer tracer(dev(), file);
              write_png(png, render(tracer, view_camera(file.bounds, "iso"), r).image);
            }),
            3u);
}

TEST_P(IoFaults, PointsBuild) {
  const std::string dir = scratch("faults_points");
  PointFileOptions o;
  o.input = point_cloud(dir);
  o.build.max_node_points = 256;
  o.output = dir + "/out.mvx";
  EXPECT_GT(sweep(dir, o.output, [&] { build_points_file(dev(), o); }), 3u);
  // out of core: sorted runs written to scratch files and merged back
  o.run_points = 700;
  EXPECT_GT(sweep(dir, o.output, [&] { EXPECT_TRUE(build_points_file(dev(), o).out_of_core); }), 6u);
  o.run_points = 0;
  o.format = PointOutput::tiles3d;
  o.output = dir + "/tiles";
  EXPECT_GT(sweep(dir, o.output, [&] { build_points_file(dev(), o); }), 3u);
}

MV_INSTANTIATE_ON_ALL_DEVICES(IoFaults);

}  // namespace
}  // namespace mv::test
