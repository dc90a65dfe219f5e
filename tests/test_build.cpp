// The main job end to end: mesh files in, .mvx out. PLY and OBJ of one mesh give the same voxels; bad inputs
// are clear errors that leave no output file.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <span>
#include <random>

#include "io/ply_reader.h"
#include "megavox/build.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "test_support.h"
#include "option_words.h"

namespace mv::test {
namespace {

namespace fs = std::filesystem;

// A bumpy closed mesh (a displaced icosphere-like grid on a sphere): vertices and triangles.
void bumpy_sphere(std::vector<float>& pos, std::vector<uint32_t>& idx, int rings = 24, int segs = 48) {
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s < segs; ++s) {
      double th = M_PI * r / rings, ph = 2 * M_PI * s / segs;
      double rad = 1.0 + 0.15 * std::sin(5 * th) * std::cos(3 * ph);
      pos.insert(pos.end(), {float(rad * std::sin(th) * std::cos(ph)), float(rad * std::cos(th)),
                             float(rad * std::sin(th) * std::sin(ph) * 0.7)});
    }
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segs; ++s) {
      uint32_t a = r * segs + s, b = r * segs + (s + 1) % segs, c = a + segs, d = b + segs;
      idx.insert(idx.end(), {a, c, b, b, c, d});
    }
}

// The bumpy sphere written as a binary PLY in the temp folder; returns its path.
std::string sphere_ply(const std::string& name, int rings = 24, int segs = 48) {
  std::vector<float> pos;
  std::vector<uint32_t> idx;
  bumpy_sphere(pos, idx, rings, segs);
  const std::string ply = temp_path(name);
  write_ply(ply, pos, idx);
  return ply;
}

std::vector<uint32_t> built_words(Device& dev, const std::string& input, const std::string& format) {
  BuildOptions o;
  o.input = input;
  o.output = temp_path("out.mvx");
  o.resolution = 256;
  o.encoding = parse_encoding(format);
  build_mvx(dev, o);
  MvxFile f = read_mvx(o.output);
  fs::remove(o.output);
  return f.dag.words;
}

class BuildJobTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST_P(BuildJobTest, ObjAndPlyGiveTheSameVoxels) {
  std::vector<float> pos;
  std::vector<uint32_t> idx;
  bumpy_sphere(pos, idx);
  const std::string ply = temp_path("mesh.ply"), obj = temp_path("mesh.obj");
  write_ply(ply, pos, idx);
  write_obj(obj, pos, idx);
  Device& dev = shared_device(GetParam());
  auto a = built_words(dev, ply, "svdag");
  auto b = built_words(dev, obj, "svdag");
  EXPECT_FALSE(a.empty());
  EXPECT_TRUE(a == b);
  fs::remove(ply);
  fs::remove(obj);
}

TEST_P(BuildJobTest, SharedMeshAsObjMatchesItsPly) {
  MV_SKIP_WITHOUT_SHARED_DATA("meshes_misc/spot.ply");
  const std::string ply = shared_data_file("meshes_misc/spot.ply");
  io::PlyMeshReader reader(ply);
  std::vector<uint32_t> idx, all;
  while (reader.next_triangles(idx, 1 << 20)) all.insert(all.end(), idx.begin(), idx.end());
  const std::string obj = temp_path("spot.obj");
  write_obj(obj, reader.positions(), all);
  Device& dev = shared_device(GetParam());
  EXPECT_TRUE(built_words(dev, ply, "ssvdag") == built_words(dev, obj, "ssvdag"));
  fs::remove(obj);
}

TEST_P(BuildJobTest, HostMemoryBudgetIsEnforced) {
  const std::string ply = sphere_ply("budget.ply");
  Device& dev = shared_device(GetParam());
  BuildOptions o;
  o.input = ply;
  o.output = temp_path("budget.mvx");
  o.resolution = 512;
  for (uint32_t cube : {0u, 64u}) {  // in core: the voxel keys; out of core: the triangles first
    o.cube = cube;
    o.memory = cube ? 16 << 10 : 1 << 20;
    try {
      build_mvx(dev, o);
      ADD_FAILURE() << "no error under a " << o.memory << "-byte budget";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("host memory budget"), std::string::npos) << e.what();
      EXPECT_EQ(classify(e), ErrorCode::out_of_memory) << e.what();
      EXPECT_TRUE(e.settings & setting_host_memory) << e.what();
    }
    EXPECT_FALSE(fs::exists(o.output));
    o.memory = 256 << 20;
    EXPECT_GT(build_mvx(dev, o).voxels, 0u);
    fs::remove(o.output);
  }
  fs::remove(ply);
}

// Builds o.output and returns its bytes (the file is removed).
std::vector<char> built_file(Device& dev, const BuildOptions& o, BuildReport& r) {
  r = build_mvx(dev, o);
  std::vector<char> bytes = file_bytes(o.output);
  fs::remove(o.output);
  return bytes;
}

// Out of core, triangles past a quarter of --memory spill to a temporary file; the file built is the same.
TEST_P(BuildJobTest, SpilledTrianglesGiveTheSameFile) {
  const std::string ply = sphere_ply("spill.ply", 160, 320);  // 102,400 triangles: 3.7 MB in grid units
  const uint64_t pos_bytes = 161 * 320 * 12;                    // over the 2 MiB budget's 512 KiB share
  Device& dev = shared_device(GetParam());
  BuildOptions o;
  o.input = ply;
  o.resolution = 256;
  o.cube = 64;
  o.encoding = Encoding::ssvdag;
  std::vector<std::vector<char>> files;
  for (uint64_t memory : {uint64_t{1} << 30, uint64_t{2} << 20}) {
    o.memory = memory;
    o.output = temp_path("spill_" + std::to_string(memory) + ".mvx");
    BuildReport r;
    files.push_back(built_file(dev, o, r));
    EXPECT_EQ(r.spilled_bytes > 0, memory < (uint64_t{1} << 30)) << memory << "-byte budget";
    EXPECT_EQ(r.vertex_scratch_bytes, memory < (uint64_t{1} << 30) ? pos_bytes : 0u);  // 51,520 vertices
  }
  EXPECT_FALSE(files[0].empty());
  EXPECT_TRUE(files[0] == files[1]);
  fs::remove(ply);
}

// A cube that does not fit --device-memory is retried at half the size; the file is the same.
TEST_P(BuildJobTest, CubesShrinkToFitDeviceMemory) {
  const std::string ply = sphere_ply("shrink.ply");
  BuildOptions o;
  o.input = ply;
  o.resolution = 1024;
  o.cube = 512;
  o.encoding = Encoding::ssvdag;
  o.placement = parse_grid_bounds("-1.2,-1.2,-1.2,4.8");  // the sphere inside the first cube: cubes dwarf the merge
  std::vector<std::vector<char>> files;
  for (uint64_t budget : {uint64_t{0}, uint64_t{3} << 20}) {  // the default, then one a 512^3 cube overflows
    auto dev = Device::open({GetParam().selector(), budget, false});
    o.output = temp_path("shrink_" + std::to_string(budget) + ".mvx");
    BuildReport r;
    files.push_back(built_file(*dev, o, r));
    if (budget) {
      EXPECT_GT(r.cube_retries, 0u);
      EXPECT_LT(r.cube, 512u);
    } else {
      EXPECT_EQ(r.cube_retries, 0u);
    }
  }
  EXPECT_FALSE(files[0].empty());
  EXPECT_TRUE(files[0] == files[1]);
  fs::remove(ply);
}

TEST_P(BuildJobTest, BadInputsAreClearErrorsAndWriteNothing) {
  Device& dev = shared_device(GetParam());
  BuildOptions o;
  o.output = temp_path("never.mvx");
  o.resolution = 64;
  auto expect_error = [&](const std::string& input, const std::string& words) {
    o.input = input;
    try {
      build_mvx(dev, o);
      ADD_FAILURE() << input << ": no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(o.output));
    EXPECT_FALSE(fs::exists(o.output + ".tmp"));
  };
  expect_error(temp_path("no_such_mesh.ply"), "no_such_mesh.ply");
  const std::string bad_obj = temp_path("bad.obj");
  std::ofstream(bad_obj) << "v 0 0 0\nv 1 0 0\nf 1 2 9\nthis is not obj\n";
  expect_error(bad_obj, "bad.obj");
  const std::string bad_ply = temp_path("bad.ply");
  std::ofstream(bad_ply) << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n1\n";
  expect_error(bad_ply, "bad.ply");
  try {
    parse_encoding("octree");
    ADD_FAILURE() << "no error for the encoding 'octree'";
  } catch (const CodedError& e) {
    EXPECT_EQ(e.code, ErrorCode::invalid_argument);
    EXPECT_EQ(e.settings, setting_encoding);
    EXPECT_NE(std::string(e.what()).find("choose svo, svdag, ussvdag or ssvdag"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_resolution("1000"), Error);
  EXPECT_THROW(parse_resolution("4M"), Error);
  EXPECT_EQ(parse_resolution("16K"), 16384u);
  fs::remove(bad_obj);
  fs::remove(bad_ply);
}

// The plan is announced once, before the voxels are built, and plan_build gives the same without a device. The
// bumpy sphere is smooth at a voxel's scale, so the voxel estimate lands near the count.
TEST_P(BuildJobTest, PlanIsAnnouncedOnceAndEstimatesTheVoxels) {
  Device& dev = shared_device(GetParam());
  BuildOptions o;
  o.input = sphere_ply("plan.ply");
  o.output = temp_path("plan.mvx");
  o.resolution = 256;
  uint32_t announced = 0;
  BuildPlan plan;
  const BuildReport r = build_mvx(dev, o, {}, [&](const BuildPlan& p) {
    ++announced;
    plan = p;
    EXPECT_FALSE(fs::exists(o.output));
  });
  EXPECT_EQ(announced, 1u);
  EXPECT_EQ(plan.resolution, 256u);
  EXPECT_EQ(plan.voxel_size, r.grid.voxel_size);
  EXPECT_FALSE(plan.out_of_core);
  EXPECT_EQ(plan.triangles, r.triangles);
  EXPECT_NEAR(double(plan.voxels) / double(r.voxels), 1.0, 0.1) << plan.voxels << " estimated, " << r.voxels;
  EXPECT_EQ(r.plan.voxels, plan.voxels);
  EXPECT_GT(plan.output_bytes, 0u);
  EXPECT_GT(plan.host_bytes, 0u);
  EXPECT_GT(plan.device_bytes, 0u);
  EXPECT_EQ(plan_build(o).voxels, plan.voxels);
  o.cube = 64;
  const BuildPlan cubes = plan_build(o);
  EXPECT_TRUE(cubes.out_of_core);
  EXPECT_EQ(cubes.cube, 64u);
  EXPECT_EQ(cubes.cubes, 64u);
  EXPECT_GE(cubes.cubes_with_surface, 1u);
  EXPECT_LE(cubes.cubes_with_surface, 64u);
  fs::remove(o.output);
  fs::remove(o.input);
}

MV_INSTANTIATE_ON_ALL_DEVICES(BuildJobTest);

}  // namespace
}  // namespace mv::test
