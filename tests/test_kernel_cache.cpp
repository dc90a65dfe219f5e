// The kernel cache: a device's first use compiles its programs (OpenCL) or has the driver compile its pipelines
// (Vulkan) and says so (DeviceOptions::on_compile); a later device on the same cache says nothing, and its
// kernels compute the same.
#include <filesystem>

#include "reference.h"
#include "common/morton.h"
#include "test_support.h"

namespace mv::test {
namespace {

class KernelCacheTest : public ::testing::TestWithParam<DeviceInfo> {};

// Morton keys of a few points computed on `d`, checked against the reference.
void expect_morton_keys(Device& d) {
  constexpr uint32_t kPoints = 256;
  std::vector<uint32_t> xyz = random_u32(3 * kPoints, 3);
  for (uint32_t& c : xyz) c &= 0x1fffff;
  Buffer pts = d.alloc(xyz.size() * 4, "points"), keys = d.alloc(uint64_t{kPoints} * 8, "keys");
  d.upload(pts, xyz.data(), xyz.size() * 4);
  d.dispatch(d.kernel(KernelId::morton_encode64), kPoints / 64, 64, {&pts, &keys}, MvMortonParams{kPoints, 0});
  std::vector<uint64_t> got(kPoints);
  d.download(keys, got.data(), got.size() * 8);
  for (uint32_t i = 0; i < kPoints; ++i)
    ASSERT_EQ(got[i], ref::morton3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], 21)) << "at " << i;
}

TEST_P(KernelCacheTest, ColdCacheReportsItsCompilesAndWarmCacheNone) {
  const std::string cache = temp_path("kernel_cache_" + device_test_name({GetParam(), 0}));
  std::vector<CompileEvent> events;
  DeviceOptions o;
  o.selector = GetParam().selector();
  o.memory_budget = 64u << 20;
  o.kernel_cache = cache;
  o.on_compile = [&](const CompileEvent& e) { events.push_back(e); };
  {
    auto d = Device::open(o);
    expect_morton_keys(*d);
    d->kernel(KernelId::scan_reduce);
  }
  // Each compile announced as it starts and as it ends, counted.
  ASSERT_GE(events.size(), 2u);
  ASSERT_EQ(events.size() % 2, 0u);
  for (uint32_t i = 0; i < events.size(); ++i) {
    EXPECT_EQ(events[i].device, GetParam().name);
    EXPECT_EQ(events[i].count, i / 2 + 1);
    EXPECT_EQ(events[i].done, i % 2 == 1);
  }
  if (GetParam().backend == "opencl") {  // morton's program and scan's, once each
    ASSERT_EQ(events.size(), 4u);
    EXPECT_EQ(events[0].program, "morton/morton.cl");
    EXPECT_EQ(events[2].program, "scan/scan.cl");
  } else {  // the one pipeline dispatched: a kernel only asked for makes none
    ASSERT_EQ(events.size(), 2u);
    EXPECT_EQ(events[0].program, "morton_encode64 (64x1)");
  }
  EXPECT_FALSE(std::filesystem::is_empty(cache));

  events.clear();
  auto warm = Device::open(o);
  expect_morton_keys(*warm);  // OpenCL: from the cached binary
  warm->kernel(KernelId::scan_reduce);
  EXPECT_TRUE(events.empty()) << events.size() << " compile events on a warm cache, the first for "
                              << events.front().program;
}

// A cache file the driver rejects (torn, or another driver's) is compiled again and replaced, not an error.
// A damaged cache file never gives wrong results: OpenCL's binary is compiled again and replaced; Vulkan's
// record only says a pipeline was compiled (the driver's cache holds the code), so the kernel runs as before.
TEST_P(KernelCacheTest, DamagedCacheFilesAreCompiledAgain) {
  const std::string cache = temp_path("damaged_cache_" + device_test_name({GetParam(), 0}));
  DeviceOptions o;
  o.selector = GetParam().selector();
  o.memory_budget = 64u << 20;
  o.kernel_cache = cache;
  expect_morton_keys(*Device::open(o));  // fills the cache
  std::vector<std::string> files;
  for (const auto& f : std::filesystem::directory_iterator(cache)) files.push_back(f.path());
  ASSERT_FALSE(files.empty());
  for (const std::string& f : files) write_bytes(f, {'n', 'o', 't'});
  expect_morton_keys(*Device::open(o));
  if (GetParam().backend == "opencl")
    for (const std::string& f : files) EXPECT_GT(std::filesystem::file_size(f), 3u) << f;
}

MV_INSTANTIATE_ON_ALL_DEVICES(KernelCacheTest);

}  // namespace
}  // namespace mv::test
