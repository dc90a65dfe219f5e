// Test helpers: every kernel test runs on every device found (the test name carries it), each device
// opened once per test process.
#pragma once
#include <gtest/gtest.h>

#include <random>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "megavox/dag_types.h"
#include "megavox/device.h"
#include "megavox/encode.h"
#include "megavox/mvx.h"
#include "megavox/error.h"
#include "megavox/ray.h"
#include "megavox/voxelize.h"

namespace mv::test {

// All devices megavox sees. Read once. May be empty (see MV_INSTANTIATE_ON_ALL_DEVICES).
const std::vector<DeviceInfo>& all_devices();

// The device for `info`, opened on first use with the default budget and kept for the process.
Device& shared_device(const DeviceInfo& info);

// Every byte of a file (empty when it cannot be read).
std::vector<char> file_bytes(const std::string& path);

// Writes `bytes` as the whole file at `path` (a test's damaged or hand-made input).
void write_bytes(const std::string& path, const std::vector<char>& bytes);

// A path for `name` in this test process's own temporary folder, removed at exit: ctest runs a test's
// instances for the different devices at the same time.
std::string temp_path(const std::string& name);

// "pocl_ocl0", "llvmpipe_vk0": a gtest-safe name that carries the backend.
std::string device_test_name(const ::testing::TestParamInfo<DeviceInfo>& info);

// Where a file of the shared test data (${MEGAVOX_TEST_DATA:-<source>/../shared/data}) is or would be.
std::string shared_data_path(const std::string& relative);
// That file, or "" when it is absent (a user's machine has no shared data; see MV_SKIP_WITHOUT_SHARED_DATA).
std::string shared_data_file(const std::string& relative);

// The triangles of a mesh file in grid units (9 floats each) on a grid placed by `placement`.
std::vector<float> mesh_grid_triangles(const std::string& path, uint32_t resolution, const GridPlacement& placement = {});

// An octahedron (8 triangles; its bottom vertex at y = `bottom`) placed on a grid of `resolution` voxels
// per axis and given in grid units (9 floats per triangle), ready for a Voxelizer.
std::vector<float> octahedron_grid_triangles(uint32_t resolution, float bottom = -1.0f);

// Every encoding of a voxel DAG.
inline constexpr Encoding kEncodings[] = {Encoding::svo, Encoding::svdag, Encoding::ussvdag, Encoding::ssvdag};

// The voxels in one encoding, on a grid of unit voxels at the origin (world = grid units).
MvxFile unit_grid_file(Device& dev, const std::vector<uint64_t>& voxels, uint32_t levels, Encoding e);

// Voxel sets (sorted unique 64-bit Morton keys of a 2^levels grid) with little, some and much sharing:
// "random" (3000 random voxels), "shell" (a sphere's shell), "tiled" (a repeating pattern), "one voxel".
std::vector<std::pair<std::string, std::vector<uint64_t>>> voxel_sets(uint32_t levels);

// The octree of sorted unique Morton keys in a 2^levels grid (level 1 = 2^3 masks), optionally reduced to its
// minimal DAG by plain maps: built on the host, so a test of the encodings or of paging needs no device.
Dag host_dag(const std::vector<uint64_t>& voxels, uint32_t levels, bool reduce);

// Writes a binary little-endian PLY: vertices `pos` (3 floats each), triangles `idx` (3 indices each).
void write_ply(const std::string& path, const std::vector<float>& pos, const std::vector<uint32_t>& idx);
// Writes the same as a Wavefront OBJ (text: read through assimp).
void write_obj(const std::string& path, std::span<const float> pos, const std::vector<uint32_t>& idx);

// Morton keys sorted, each once.
std::vector<uint64_t> sorted_unique(std::vector<uint64_t> keys);

// Asserts two traces' hits are the same in every field (none coarse); returns how many rays hit.
size_t expect_same_hits(const std::vector<RayHit>& got, const std::vector<RayHit>& want);

// The message of the mv::Error `f` throws ("" when it throws none).
template <class F>
std::string error_message(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// Deterministic random data.
std::vector<uint32_t> random_u32(size_t n, uint64_t seed);
std::vector<uint64_t> random_u64(size_t n, uint64_t seed);

}  // namespace mv::test

// Parameterizes `suite` over every device. With none found the suite has no tests, which is allowed here:
// Environment.SomeDeviceIsFound fails instead, saying what to install.
#define MV_INSTANTIATE_ON_ALL_DEVICES(suite)                                                                          \
  INSTANTIATE_TEST_SUITE_P(Devices, suite, ::testing::ValuesIn(::mv::test::all_devices()),                            \
                           ::mv::test::device_test_name);                                                             \
  GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(suite)

// Skips the running test, with one line naming the missing file, unless the shared test data holds `relative`.
#define MV_SKIP_WITHOUT_SHARED_DATA(relative)                                                                         \
  do {                                                                                                                \
    if (::mv::test::shared_data_file(relative).empty())                                                               \
      GTEST_SKIP() << "shared data not found: " << ::mv::test::shared_data_path(relative)                             \
                   << " (stage ../shared/data or set MEGAVOX_TEST_DATA)";                                             \
  } while (0)

namespace mv {
// gtest prints parameters with this instead of a byte dump.
inline void PrintTo(const DeviceInfo& d, std::ostream* os) { *os << d.selector() << " (" << d.name << ")"; }
}  // namespace mv
