// Voxelizer edge cases, each on every device against the CPU reference (host/ref) under both rules: triangles
// lying on voxel faces (the grid's top face too), along voxel edges and through voxel corners; slivers and
// degenerate triangles; triangles on brick (4^3) and tile boundaries; triangles larger than an out-of-core
// cube; random small triangles. Then one cube against many, for the Voxelizer's cube restriction and for
// whole builds (the same file bytes in every format). Only public behaviour is used, so the cases hold
// whatever the kernels do inside.
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "reference.h"
#include "megavox/build.h"
#include "megavox/encode.h"
#include "megavox/mvx.h"
#include "megavox/voxelize.h"
#include "test_support.h"
#include "option_words.h"

namespace mv::test {
namespace {

using Tri = std::array<float, 9>;
using Rule = Voxelizer::Rule;
constexpr Rule kRules[] = {Rule::kConservative, Rule::kThin};

const char* name(Rule r) { return r == Rule::kThin ? "thin" : "conservative"; }

void push(std::vector<float>& out, const Tri& t) { out.insert(out.end(), t.begin(), t.end()); }

// The triangle with its coordinates' axes shifted (x -> y -> z), so a case written in one orientation covers
// all three; and with its winding reversed (the normal flipped) and its vertices rotated, since which vertex
// comes first may matter to a kernel even though it must not to the voxels.
Tri shift_axes(const Tri& t, int shift) {
  Tri r;
  for (int p = 0; p < 3; ++p)
    for (int a = 0; a < 3; ++a) r[3 * p + (a + shift) % 3] = t[3 * p + a];
  return r;
}
Tri reversed(const Tri& t) { return {t[0], t[1], t[2], t[6], t[7], t[8], t[3], t[4], t[5]}; }
Tri rotated(const Tri& t) { return {t[3], t[4], t[5], t[6], t[7], t[8], t[0], t[1], t[2]}; }

// Every axis order and both windings of each triangle; with `all_starts`, each vertex first as well.
std::vector<float> every_orientation(std::initializer_list<Tri> tris, bool all_starts = false) {
  std::vector<float> out;
  for (const Tri& base : tris)
    for (int shift = 0; shift < 3; ++shift) {
      Tri t = shift_axes(base, shift);
      for (int start = 0; start < (all_starts ? 3 : 1); ++start, t = rotated(t)) {
        push(out, t);
        push(out, reversed(t));
      }
    }
  return out;
}

// The device's voxels of `tris` (grid units, n voxels per axis), optionally only those of one cube.
std::vector<uint64_t> device_voxels(Device& dev, const std::vector<float>& tris, uint32_t n, Rule rule,
                                    const uint32_t* cube = nullptr, uint32_t size = 0) {
  Voxelizer v(dev, n, rule);
  if (cube) v.restrict_to(cube[0], cube[1], cube[2], size);
  v.add(tris);
  return v.take_keys();
}

// The device voxelizer against the reference, both rules: for the whole set (each triangle in its own
// Voxelizer too when `each`, so a voxel one triangle misses cannot hide behind another triangle's).
void expect_reference(Device& dev, const std::string& what, const std::vector<float>& tris, uint32_t n,
                      bool each = true) {
  for (Rule rule : kRules) {
    SCOPED_TRACE(what + ", " + name(rule) + ", grid " + std::to_string(n));
    const std::vector<uint64_t> expect = ref::voxelize(tris, n, rule == Rule::kThin);
    const std::vector<uint64_t> got = device_voxels(dev, tris, n, rule);
    ASSERT_EQ(got.size(), expect.size());
    ASSERT_TRUE(got == expect);
    for (size_t t = 0; each && t < tris.size(); t += 9) {
      const std::vector<float> one(tris.begin() + t, tris.begin() + t + 9);
      ASSERT_TRUE(device_voxels(dev, one, n, rule) == ref::voxelize(one, n, rule == Rule::kThin))
          << "triangle " << t / 9;
    }
  }
}

// Triangles in the grid plane z = k of an n^3 grid (then x = k and y = k): generic, with integer vertices
// and edges along grid lines, a half voxel face, a small one inside a face, and the whole plane of the grid.
std::vector<float> on_face(float k, float n) {
  return every_orientation({{0.3f, 0.4f, k, 5.7f, 1.2f, k, 2.2f, 6.9f, k},
                            {2, 3, k, 6, 3, k, 2, 7, k},
                            {2, 3, k, 3, 3, k, 2, 4, k},
                            {4.25f, 4.25f, k, 4.5f, 4.25f, k, 4.25f, 4.5f, k},
                            {0, 0, k, n, 0, k, 0, n, k},
                            {n, n, k, 0, n, k, n, 0, k}});
}

// The planes from the bottom face of a 16^3 grid to its top one (which belongs to the last voxel).
constexpr float kFacePlanes[] = {0, 1, 7, 8, 15, 16};

std::vector<float> on_faces(float n) {
  std::vector<float> out;
  for (float k : kFacePlanes) {
    std::vector<float> plane = on_face(k, n);
    out.insert(out.end(), plane.begin(), plane.end());
  }
  return out;
}

// Bits 3i + axis of a 64-bit Morton key: the voxel's coordinate along that axis.
uint32_t coordinate(uint64_t key, int axis) {
  uint32_t c = 0;
  for (int i = 0; i < 21; ++i) c |= uint32_t((key >> (3 * i + axis)) & 1) << i;
  return c;
}

// Triangles with an edge along a grid line (a voxel edge) that do not lie in a grid plane: leaning away, in
// the diagonal plane x - y = -1 (through voxel edges), nearly in a grid plane, on the grid's outer edges.
std::vector<float> along_edges(float n) {
  return every_orientation({{2, 3, 1, 2, 3, 9, 5.5f, 7.25f, 4.1f},
                            {2, 3, 1, 2, 3, 9, 6, 7, 5},
                            {2, 3, 1, 2, 3, 9, 6, 3.0625f, 5},
                            {1, 1, 1, 9, 1, 1, 9, 9, 9},
                            {0, 0, 0, 0, 0, n, 3.7f, 2.1f, 8},
                            {n, n, 2, n, n, 12, n - 5.5f, n - 2.7f, 7},
                            {n, 0, 3, n, 0, 11, n - 4, 4, 7}});
}

// Triangles through voxel corners: planes x + y + z = 8 and 16 through lattice points, triangles touching a
// corner with one vertex from below and from above, an edge passing through a corner, the grid's corners.
std::vector<float> through_corners(float n) {
  return every_orientation({{6, 1, 1, 1, 6, 1, 1, 1, 6},
                            {0, 0, n, n, 0, 0, 0, n, 0},
                            {4, 4, 4, 3.5f, 3, 3.25f, 3, 3.625f, 3.125f},
                            {4, 4, 4, 4.5f, 5, 4.75f, 5, 4.375f, 4.875f},
                            {4, 4, 4, 5.5f, 2.5f, 4.25f, 2.75f, 5.75f, 3.5f},
                            {3, 3, 3, 5, 5, 5, 2.5f, 6.1f, 4.2f},
                            {n, n, n, n - 1.5f, n, n - 0.75f, n, n - 1.25f, n - 0.5f},
                            {0, 0, 0, 1.5f, 0.25f, 0.75f, 0.25f, 1.25f, 0.875f}});
}

// Very thin, nearly collinear and long triangles in a 64^3 grid: across the diagonal, along a grid line, in a
// grid plane, a needle along an axis, and one a float ulp wide on the diagonal through the lattice corners.
std::vector<float> slivers(float n) {
  const float ulp = std::nextafter(n, 0.0f);
  return every_orientation({{0.3f, 0.3f, 0.3f, n - 0.3f, n - 0.5f, n - 0.7f, n - 0.3f, n - 0.499f, n - 0.7f},
                            {1, 1, 1, n - 1, n - 1, n - 1, n / 2, n / 2 + 1e-4f, n / 2},
                            {0, 2, 3, n, 2, 3, n, 2.0001f, 3},
                            {0.1f, 0.1f, 8, n - 0.1f, n - 0.3f, 8, n - 0.1f, n - 0.2999f, 8},
                            {1.5f, 1.5f, 0, 1.5f, 1.5f, n, 1.5001f, 1.5f, n},
                            {0, 0, 0, n, n, n, n, n, ulp},
                            {4, 4, 4, n - 4, n - 4, n - 4, n - 3.999f, n - 4, n - 4},
                            {10.2f, 10.3f, 10.4f, 10.25f, 10.3f, 10.4f, 13.9f, 10.31f, 10.4f}});
}

// Segments and points: three collinear vertices (on lattice points, along a grid line, off the lattice, the
// middle one last), two equal vertices, all three equal (on a corner, an edge, a face, a voxel's centre, the
// grid's top corner and face, the origin). Each vertex goes first once, so the repeated one moves around.
std::vector<float> degenerate(float n) {
  return every_orientation({{1, 2, 3, 3, 4, 5, 5, 6, 7},
                            {2, 3, 0, 2, 3, 5, 2, 3, 9},
                            {1.25f, 2.5f, 3.75f, 2.5f, 5, 7.5f, 3.75f, 7.5f, 11.25f},
                            {1, 1, 1, 9, 9, 9, 5, 5, 5},
                            {2, 3, 4, 2, 3, 4, 7, 8, 9},
                            {2.3f, 3.1f, 4.7f, 2.3f, 3.1f, 4.7f, 7.6f, 1.2f, 9.9f},
                            {2, 3, 4, 2, 3, 4, 2, 3, 9},
                            {5, 5, 5, 5, 5, 5, 5, 5, 5},
                            {5, 5, 5.5f, 5, 5, 5.5f, 5, 5, 5.5f},
                            {5, 5.5f, 5.5f, 5, 5.5f, 5.5f, 5, 5.5f, 5.5f},
                            {5.5f, 5.5f, 5.5f, 5.5f, 5.5f, 5.5f, 5.5f, 5.5f, 5.5f},
                            {n, n, n, n, n, n, n, n, n},
                            {n, 3.5f, 7.25f, n, 3.5f, 7.25f, n, 3.5f, 7.25f},
                            {0, 0, 0, 0, 0, 0, 0, 0, 0}},
                           true);
}

// Triangles on the boundaries of aligned blocks of s^3 voxels in a 256^3 grid, s = 4 (bricks) up to 128: the
// tile size is the voxelizer's choice, so every power of two is covered. At the first boundary c = s and at
// the last one c = 256 - s: in the boundary plane across the boundary lines, across the corner (c,c,c), a
// vertex on it, an edge along a boundary line, and one crossing a whole block (capped at 16 voxels).
std::vector<float> block_boundaries() {
  std::vector<float> out;
  for (float s : {4.0f, 8.0f, 16.0f, 32.0f, 64.0f, 128.0f})
    for (float c : {s, 256 - s}) {
      const float w = std::min(s, 16.0f);
      std::vector<float> block = every_orientation(
          {{c, c - 1.5f, c - 2.25f, c, c + 2.75f, c - 0.5f, c, c + 0.25f, c + 3.5f},
           {c - 0.5f, c - 0.25f, c - 0.75f, c + 0.5f, c + 0.25f, c - 0.5f, c - 0.25f, c + 0.625f, c + 0.375f},
           {c, c, c, c + 1.5f, c - 2, c + 0.5f, c - 1, c + 2.5f, c + 1.25f},
           {c, c, c - 3, c, c, c + 3, c + 2.5f, c - 1.5f, c + 0.5f},
           {c - w, c - w + 0.5f, c - 0.3f, c + w - 0.5f, c + 0.2f, c + 0.7f, c + 0.1f, c + w - 0.25f, c - w + 0.4f}});
      out.insert(out.end(), block.begin(), block.end());
    }
  return out;
}

// Triangles larger than an out-of-core cube of a 256^3 grid: one across the whole grid on the diagonal, one
// in the plane x + y + 8z = 1024 through lattice points (it meets cube boundaries on grid lines), one flat in
// the plane z = 96 (a face of the cubes of 32) across 224 voxels. Few orientations: the reference tests every
// cell of their bounding boxes.
std::vector<float> larger_than_a_cube() {
  std::vector<float> out;
  push(out, {0.5f, 0.5f, 255.5f, 255.5f, 0.5f, 0.5f, 128.3f, 255.7f, 127.9f});
  for (int shift = 0; shift < 3; ++shift) {
    push(out, shift_axes({0, 0, 128, 256, 0, 96, 0, 256, 96}, shift));
    push(out, shift_axes({16, 16, 96, 240, 24, 96, 20, 240, 96}, shift));
  }
  return out;
}

// Triangles reaching out of a 16^3 grid (an explicit --bounds cube keeps them): the exact test cuts them at
// the grid's faces, also where they lie in the bottom and top faces' planes.
std::vector<float> partly_outside(float n) {
  return every_orientation({{-4, 2.5f, 3, n + 4, 5.5f, 9, 6, n + 5, -3},
                            {0, -5, 3, 0, n + 4, 4, 0, 7, n + 9},
                            {n, -5, 3, n, n + 4, 4, n, 7, n + 9},
                            {-3, -3, -3, n + 3, n + 3, n + 3, n + 3, -2, 5}});
}

// Small triangles at random in a 32^3 grid (fixed seed): half with free float vertices, half with vertices on
// the quarter-voxel lattice, so many lie exactly on faces, edges and corners.
std::vector<float> random_small(uint32_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> pos(0.0f, float(n)), step(-3.0f, 3.0f);
  std::vector<float> out;
  for (int t = 0; t < 2000; ++t) {
    Tri tri;
    for (int a = 0; a < 3; ++a) tri[a] = pos(rng);
    for (int p = 1; p < 3; ++p)
      for (int a = 0; a < 3; ++a) tri[3 * p + a] = std::clamp(tri[a] + step(rng), 0.0f, float(n));
    if (t % 2)
      for (float& c : tri) c = std::round(c * 4) / 4;
    push(out, tri);
  }
  return out;
}

class VoxelizeEdgesTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST_P(VoxelizeEdgesTest, TrianglesOnVoxelFaces) {
  expect_reference(shared_device(GetParam()), "faces", on_faces(16), 16);
}

// Voxel i covers [i, i + 1): a triangle in the plane at k sets voxels of layer k only (both rules), and one in
// the grid's top face those of the last layer.
TEST_P(VoxelizeEdgesTest, TrianglesOnVoxelFacesSetOneLayer) {
  Device& dev = shared_device(GetParam());
  const uint32_t n = 16;
  for (float k : kFacePlanes) {
    const std::vector<float> tris = on_face(k, n);
    for (size_t t = 0; t < tris.size(); t += 9) {
      int axis = 0;
      while (tris[t + axis] != k || tris[t + 3 + axis] != k || tris[t + 6 + axis] != k) ++axis;
      const std::vector<float> one(tris.begin() + t, tris.begin() + t + 9);
      for (Rule rule : kRules) {
        const std::vector<uint64_t> keys = device_voxels(dev, one, n, rule);
        EXPECT_FALSE(keys.empty()) << "plane " << k << ", triangle " << t / 9 << ", " << name(rule);
        for (uint64_t key : keys)
          ASSERT_EQ(coordinate(key, axis), std::min<uint32_t>(uint32_t(k), n - 1))
              << "plane " << k << ", triangle " << t / 9 << ", " << name(rule);
      }
    }
  }
}

TEST_P(VoxelizeEdgesTest, TrianglesAlongVoxelEdges) {
  expect_reference(shared_device(GetParam()), "edges", along_edges(16), 16);
}

TEST_P(VoxelizeEdgesTest, TrianglesThroughVoxelCorners) {
  expect_reference(shared_device(GetParam()), "corners", through_corners(16), 16);
}

TEST_P(VoxelizeEdgesTest, Slivers) { expect_reference(shared_device(GetParam()), "slivers", slivers(64), 64); }

TEST_P(VoxelizeEdgesTest, DegenerateTriangles) {
  expect_reference(shared_device(GetParam()), "degenerate", degenerate(16), 16);
}

TEST_P(VoxelizeEdgesTest, TrianglesOnBrickAndTileBoundaries) {
  expect_reference(shared_device(GetParam()), "block boundaries", block_boundaries(), 256);
}

TEST_P(VoxelizeEdgesTest, TrianglesLargerThanACube) {
  expect_reference(shared_device(GetParam()), "larger than a cube", larger_than_a_cube(), 256, false);
}

TEST_P(VoxelizeEdgesTest, TrianglesCutAtTheGridFaces) {
  expect_reference(shared_device(GetParam()), "partly outside", partly_outside(16), 16);
}

TEST_P(VoxelizeEdgesTest, RandomSmallTriangles) {
  expect_reference(shared_device(GetParam()), "random", random_small(32, 24), 32, false);
}

// Cubes of 32 and 64 voxelized one at a time (Voxelizer::restrict_to, as out-of-core builds do) give the
// whole grid's voxels, each voxel in exactly the cube that holds it (a triangle on a cube face belongs to the
// cube above it).
TEST_P(VoxelizeEdgesTest, CubesTogetherGiveTheWholeGrid) {
  Device& dev = shared_device(GetParam());
  std::vector<float> tris = larger_than_a_cube(), blocks = block_boundaries();
  tris.insert(tris.end(), blocks.begin(), blocks.end());
  const uint32_t n = 256;
  for (Rule rule : kRules) {
    const std::vector<uint64_t> whole = device_voxels(dev, tris, n, rule);
    for (uint32_t size : {32u, 64u}) {
      SCOPED_TRACE(std::string(name(rule)) + ", cubes of " + std::to_string(size));
      std::vector<uint64_t> all;
      for (uint32_t x = 0; x < n; x += size)
        for (uint32_t y = 0; y < n; y += size)
          for (uint32_t z = 0; z < n; z += size) {
            const uint32_t cube[3] = {x, y, z};
            const std::vector<uint64_t> keys = device_voxels(dev, tris, n, rule, cube, size);
            const uint64_t first = ref::morton3(x, y, z, 21), end = first + uint64_t{size} * size * size;
            for (uint64_t k : keys) ASSERT_TRUE(k >= first && k < end) << "cube " << x << "," << y << "," << z;
            all.insert(all.end(), keys.begin(), keys.end());
          }
      std::sort(all.begin(), all.end());
      ASSERT_TRUE(all == whole);
    }
  }
}

MV_INSTANTIATE_ON_ALL_DEVICES(VoxelizeEdgesTest);

// The triangles as a PLY triangle soup whose units are voxels of the grid --bounds 0,0,0,256 at 256^3.
BuildOptions soup_build(const std::vector<float>& tris) {
  std::vector<uint32_t> idx(tris.size() / 3);
  for (uint32_t i = 0; i < idx.size(); ++i) idx[i] = i;
  BuildOptions o;
  o.input = temp_path("soup.ply");
  write_ply(o.input, tris, idx);
  o.resolution = 256;
  o.placement = parse_grid_bounds("0,0,0,256");
  return o;
}

// The built file's bytes (the file is removed) and its report.
std::vector<char> built_bytes(Device& dev, BuildOptions o, BuildReport& r) {
  o.output = temp_path("soup_" + encoding_name(o.encoding) + "_" + std::to_string(o.cube) + ".mvx");
  r = build_mvx(dev, o);
  std::vector<char> bytes = file_bytes(o.output);
  std::filesystem::remove(o.output);
  return bytes;
}

class BuildEdgesTest : public ::testing::TestWithParam<DeviceInfo> {};

// Triangles larger than a cube and on cube faces, built in core (one cube) and out of core in cubes of 64 (and
// of 32, 512 cubes, once): the same file bytes, and the voxels the reference sets. Each format has its own
// merge (svo; svdag; ussvdag and ssvdag share one); the thin rule differs only before it.
TEST_P(BuildEdgesTest, OneCubeAndManyGiveTheSameFile) {
  Device& dev = shared_device(GetParam());
  std::vector<float> tris = larger_than_a_cube(), blocks = block_boundaries();
  tris.insert(tris.end(), blocks.begin(), blocks.end());
  BuildOptions o = soup_build(tris);
  // Paged in level order, which keeps the build's own node order in the bytes compared (subtree pages are the
  // same for any order of the nodes within a level).
  o.paging = {1024, NodeOrder::level};
  const struct {
    Rule rule;
    const char* format;
    std::vector<uint32_t> cubes;
  } builds[] = {{Rule::kConservative, "svdag", {64}},  {Rule::kConservative, "svo", {64}},
                {Rule::kConservative, "ussvdag", {64}}, {Rule::kConservative, "ssvdag", {64, 32}},
                {Rule::kThin, "svdag", {64}},          {Rule::kThin, "ssvdag", {64}}};
  for (const auto& b : builds) {
    SCOPED_TRACE(std::string(name(b.rule)) + ", " + b.format);
    o.voxelize = b.rule;
    o.encoding = parse_encoding(b.format);
    o.cube = 0;
    BuildReport r;
    const std::vector<char> in_core = built_bytes(dev, o, r);
    ASSERT_EQ(r.cube, 0u);
    if (o.encoding == Encoding::svdag) {  // the file holds the reference's voxels
      const std::string path = temp_path("soup_check.mvx");
      std::ofstream(path, std::ios::binary).write(in_core.data(), std::streamsize(in_core.size()));
      EXPECT_TRUE(decode_encoded(read_mvx(path).dag) == ref::voxelize(tris, 256, b.rule == Rule::kThin));
    }
    for (uint32_t cube : b.cubes) {
      o.cube = cube;
      EXPECT_TRUE(built_bytes(dev, o, r) == in_core) << "cubes of " << cube;
      EXPECT_EQ(r.cube, cube);
    }
  }
}

MV_INSTANTIATE_ON_ALL_DEVICES(BuildEdgesTest);

}  // namespace
}  // namespace mv::test
