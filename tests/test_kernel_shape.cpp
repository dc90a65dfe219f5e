// --kernel-shape: each device opened with GPU-shaped and with CPU-shaped launches runs the other family of
// variants (the cooperative or the block-per-work-item radix sort, grid-stride or block launches, work-groups
// of 64 or of the device's own width), and both give the same bytes: sorts, a voxel build, a point build and
// min-cuts.
#include <cmath>
#include <filesystem>
#include <random>

#include "megavox/build.h"
#include "megavox/min_cut.h"
#include "megavox/point_build.h"
#include "megavox/primitives.h"
#include "point_fixture.h"
#include "test_support.h"

namespace mv::test {
namespace {

namespace fs = std::filesystem;

std::unique_ptr<Device> open_shaped(const DeviceInfo& d, KernelShape shape) {
  DeviceOptions o;
  o.selector = d.selector();
  o.memory_budget = uint64_t{512} << 20;
  o.kernel_shape = shape;
  return Device::open(o);
}

// A torus of `rings` x `segs` quads, as a binary PLY in the temp folder.
std::string shape_torus_ply(const std::string& name) {
  const int rings = 40, segs = 24;
  std::vector<float> pos;
  std::vector<uint32_t> idx;
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segs; ++s) {
      const double a = 2 * M_PI * r / rings, b = 2 * M_PI * s / segs, rad = 1.0 + 0.35 * std::cos(b);
      pos.insert(pos.end(), {float(rad * std::cos(a)), float(0.35 * std::sin(b)), float(rad * std::sin(a))});
    }
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segs; ++s) {
      const uint32_t p = r * segs + s, q = r * segs + (s + 1) % segs, u = ((r + 1) % rings) * segs + s,
                     v = ((r + 1) % rings) * segs + (s + 1) % segs;
      idx.insert(idx.end(), {p, u, q, q, u, v});
    }
  const std::string path = temp_path(name);
  write_ply(path, pos, idx);
  return path;
}

// A clustered cloud with colours, as a binary PLY in the temp folder.
std::string shape_cloud_ply(const std::string& name, size_t n) {
  std::mt19937_64 rng(17);
  std::normal_distribution<double> around(0, 1);
  std::uniform_int_distribution<int> centre(0, 5), colour(0, 255);
  std::vector<points::PlyColumn> cols = {{"float", "x", {}},   {"float", "y", {}},     {"float", "z", {}},
                                         {"uchar", "red", {}}, {"uchar", "green", {}}, {"uchar", "blue", {}}};
  for (size_t i = 0; i < n; ++i) {
    const int c = centre(rng);
    cols[0].values.push_back(c * 10 + around(rng) * (1 + c));
    cols[1].values.push_back(-c * 3 + around(rng));
    cols[2].values.push_back(around(rng) * 0.1 * (c + 1));
    for (int k = 3; k < 6; ++k) cols[k].values.push_back(colour(rng));
  }
  const std::string path = temp_path(name);
  const std::string bytes = points::make_cloud_ply(ply::Fmt::le, cols);
  write_bytes(path, std::vector<char>(bytes.begin(), bytes.end()));
  return path;
}

// An image-like 8-connected grid: a bright blob on noise, GrabCut-shaped integer weights.
GridGraph shape_blob_graph(uint32_t w, uint32_t h, uint32_t conn) {
  static constexpr int dx[8] = {1, -1, 0, 0, 1, -1, 1, -1}, dy[8] = {0, 0, 1, -1, 1, -1, -1, 1};
  GridGraph g;
  g.width = w, g.height = h, g.connectivity = conn;
  g.source.assign(size_t{w} * h, 0);
  g.sink.assign(size_t{w} * h, 0);
  g.edges.assign(size_t{w} * h * conn, 0);
  std::mt19937_64 rng(23);
  std::normal_distribution<double> noise(0, 35);
  std::vector<double> v(size_t{w} * h);
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const double ex = x - 0.4 * w, ey = y - 0.6 * h;
      v[size_t{y} * w + x] = (ex * ex + ey * ey < 0.08 * w * h ? 185 : 65) + noise(rng);
    }
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x) {
      const size_t i = size_t{y} * w + x;
      g.source[i] = static_cast<uint32_t>(std::abs(v[i] - 65));
      g.sink[i] = static_cast<uint32_t>(std::abs(v[i] - 185));
      for (uint32_t d = 0; d < conn; ++d) {
        const long nx = long{x} + dx[d], ny = long{y} + dy[d];
        if (nx < 0 || ny < 0 || nx >= long{w} || ny >= long{h}) continue;
        const double diff = v[i] - v[size_t(ny) * w + size_t(nx)];
        g.edges[i * conn + d] = static_cast<uint32_t>(50.0 * std::exp(-diff * diff / 3000));
      }
    }
  return g;
}

class KernelShapeTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST_P(KernelShapeTest, ForcedShapesSetTheLaunchFields) {
  auto gpu = open_shaped(GetParam(), KernelShape::gpu);
  auto cpu = open_shaped(GetParam(), KernelShape::cpu);
  EXPECT_TRUE(gpu->info().massively_parallel);
  EXPECT_EQ(gpu->info().preferred_work_group_size, std::min(64u, GetParam().max_work_group_size));
  EXPECT_FALSE(cpu->info().massively_parallel);
  EXPECT_LE(cpu->info().preferred_work_group_size, GetParam().simd_width);
  // The lock-step width is the device's own, whatever the shape (Vulkan: its real subgroup size).
  EXPECT_EQ(gpu->info().simd_width, GetParam().simd_width);
  EXPECT_EQ(cpu->info().simd_width, GetParam().simd_width);
  EXPECT_EQ(kernel_shape_name(parse_kernel_shape("gpu")), std::string("gpu"));
  EXPECT_THROW(parse_kernel_shape("wide"), CodedError);
}

TEST_P(KernelShapeTest, BothShapesGiveTheSameBytes) {
  auto gpu = open_shaped(GetParam(), KernelShape::gpu);
  auto cpu = open_shaped(GetParam(), KernelShape::cpu);
  Device* devs[2] = {gpu.get(), cpu.get()};

  {  // Radix sort, keys and values, both key widths; Auto picks the shape's variant.
    const std::vector<uint64_t> keys64 = random_u64(300000, 5);
    std::vector<uint32_t> keys32 = random_u32(300000, 6);
    for (auto& k : keys32) k &= 0xffff;  // many equal keys: stability shows
    std::vector<uint32_t> iota(keys64.size());
    for (size_t i = 0; i < iota.size(); ++i) iota[i] = uint32_t(i);
    std::vector<uint64_t> k64[2];
    std::vector<uint32_t> k32[2], v64[2], v32[2];
    SortReport reports[2];
    for (int s = 0; s < 2; ++s) {
      k64[s] = keys64, v64[s] = iota, k32[s] = keys32, v32[s] = iota;
      reports[s] = radix_sort(*devs[s], k64[s], &v64[s]);
      radix_sort(*devs[s], k32[s], &v32[s]);
    }
    EXPECT_EQ(reports[0].cooperative, cooperative_sort_fits(gpu->info()));
    EXPECT_FALSE(reports[1].cooperative);
    EXPECT_EQ(k64[0], k64[1]);
    EXPECT_EQ(v64[0], v64[1]);
    EXPECT_EQ(k32[0], k32[1]);
    EXPECT_EQ(v32[0], v32[1]);
    EXPECT_TRUE(std::is_sorted(k64[0].begin(), k64[0].end()));
  }

  {  // A voxel build: the .mvx bytes.
    const std::string mesh = shape_torus_ply("shape_torus.ply");
    std::vector<char> files[2];
    for (int s = 0; s < 2; ++s) {
      BuildOptions o;
      o.input = mesh;
      o.output = temp_path(s == 0 ? "shape_gpu.mvx" : "shape_cpu.mvx");
      o.resolution = 256;
      o.encoding = Encoding::ssvdag;
      build_mvx(*devs[s], o);
      files[s] = file_bytes(o.output);
      fs::remove(o.output);
    }
    EXPECT_FALSE(files[0].empty());
    EXPECT_TRUE(files[0] == files[1]) << "the voxel builds differ";
    fs::remove(mesh);
  }

  {  // A point build: the .mvx bytes.
    const std::string cloud = shape_cloud_ply("shape_cloud.ply", 60000);
    std::vector<char> files[2];
    for (int s = 0; s < 2; ++s) {
      PointFileOptions o;
      o.input = cloud;
      o.output = temp_path(s == 0 ? "shape_points_gpu.mvx" : "shape_points_cpu.mvx");
      o.build.max_node_points = 1000;
      build_points_file(*devs[s], o);
      files[s] = file_bytes(o.output);
      fs::remove(o.output);
    }
    EXPECT_FALSE(files[0].empty());
    EXPECT_TRUE(files[0] == files[1]) << "the point builds differ";
    fs::remove(cloud);
  }

  // Min-cuts, both solvers, 4- and 8-connected.
  for (MinCutSolver solver : {MinCutSolver::regions, MinCutSolver::push_relabel})
    for (uint32_t conn : {4u, 8u}) {
      SCOPED_TRACE(std::string(solver == MinCutSolver::regions ? "regions" : "push-relabel") + ", " +
                   std::to_string(conn) + "-connected");
      const GridGraph g = shape_blob_graph(96, 70, conn);
      MinCutOptions o;
      o.solver = solver;
      const MinCut a = min_cut(*gpu, g, o), b = min_cut(*cpu, g, o);
      EXPECT_EQ(a.value, b.value);
      EXPECT_TRUE(a.source_side == b.source_side);
    }
}

MV_INSTANTIATE_ON_ALL_DEVICES(KernelShapeTest);

}  // namespace
}  // namespace mv::test
