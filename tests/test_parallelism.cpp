// The parallelism profile: its arithmetic on made-up timings, and the counters it reads on every device.
#include <gtest/gtest.h>

#include "common/morton.h"
#include "megavox/parallelism.h"
#include "test_support.h"

namespace mv::test {
namespace {

TEST(Parallelism, WidthIsUnitsTimesGroupTimesFour) {
  DeviceInfo d;
  d.compute_units = 2;
  d.preferred_work_group_size = 64;
  EXPECT_EQ(parallel_width(d), 512u);
  d.compute_units = 0;  // not reported: one unit
  d.preferred_work_group_size = 8;
  EXPECT_EQ(parallel_width(d), 32u);
}

TEST(Parallelism, SplitsTimeIntoHostDeviceAndNarrow) {
  const std::vector<KernelTiming> timings = {
      {"wide", 3'000'000'000, 4096}, {"serial", 1'000'000'000, 1}, {"wide", 1'000'000'000, 512},
      {"serial", 500'000'000, 511}};
  const Parallelism p = parallelism_profile(timings, 512, 10.0, 4.0, 1.5);
  EXPECT_DOUBLE_EQ(p.wall_seconds, 10.0);
  EXPECT_DOUBLE_EQ(p.device_seconds, 5.5);
  EXPECT_DOUBLE_EQ(p.narrow_seconds, 1.5);  // under 512 work-items; 512 itself is wide
  EXPECT_DOUBLE_EQ(p.host_seconds, 10.0 - 4.0 - 1.5);
  EXPECT_EQ(p.width, 512u);
  ASSERT_EQ(p.kernels.size(), 2u);
  EXPECT_EQ(p.kernels[0].kernel, "wide");  // most device time first
  EXPECT_EQ(p.kernels[0].launches, 2u);
  EXPECT_EQ(p.kernels[0].work_items, 4608u);
  EXPECT_DOUBLE_EQ(p.kernels[0].seconds, 4.0);
  EXPECT_DOUBLE_EQ(p.kernels[0].narrow_seconds, 0.0);
  EXPECT_EQ(p.kernels[1].kernel, "serial");
  EXPECT_DOUBLE_EQ(p.kernels[1].narrow_seconds, 1.5);
  // Waits longer than the wall (clock skew between the counters) leave no negative host time.
  EXPECT_DOUBLE_EQ(parallelism_profile({}, 1, 1.0, 0.8, 0.5).host_seconds, 0.0);
}

TEST(Parallelism, AccumulatesStages) {
  Parallelism total;
  accumulate(total, parallelism_profile({{"a", 1'000'000'000, 1}}, 64, 2.0, 1.0, 0.0));
  accumulate(total, parallelism_profile({{"b", 3'000'000'000, 64}, {"a", 1'000'000'000, 1}}, 64, 5.0, 4.0, 0.5));
  EXPECT_DOUBLE_EQ(total.wall_seconds, 7.0);
  EXPECT_DOUBLE_EQ(total.device_seconds, 5.0);
  EXPECT_DOUBLE_EQ(total.narrow_seconds, 2.0);
  EXPECT_DOUBLE_EQ(total.host_seconds, 1.0 + 0.5);
  EXPECT_EQ(total.width, 64u);
  ASSERT_EQ(total.kernels.size(), 2u);
  EXPECT_EQ(total.kernels[0].kernel, "b");
  EXPECT_EQ(total.kernels[1].launches, 2u);
}

class ParallelismDeviceTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST_P(ParallelismDeviceTest, MeterSeesDispatchesAndWaits) {
  DeviceOptions o;
  o.selector = GetParam().selector();
  o.memory_budget = 64u << 20;
  o.profile = true;
  auto d = Device::open(o);
  std::vector<uint32_t> xyz(3 * 4096, 7);
  Buffer pts = d->alloc(xyz.size() * 4, "points");
  Buffer keys = d->alloc(4096 * 8, "keys");
  d->upload(pts, xyz.data(), xyz.size() * 4);
  ParallelismMeter meter(*d);
  meter.start();
  const uint64_t waited = d->host_wait_ns();
  d->dispatch(d->kernel(KernelId::morton_encode64), 64, 64, {&pts, &keys}, MvMortonParams{4096, 0});
  d->dispatch(d->kernel(KernelId::morton_encode64), 1, 1, {&pts, &keys}, MvMortonParams{1, 0});
  std::vector<uint64_t> back(4096);
  d->download(keys, back.data(), back.size() * 8);  // waits for the dispatches
  EXPECT_GT(d->host_wait_ns(), waited);
  const Parallelism p = meter.stop();
  ASSERT_EQ(p.kernels.size(), 1u);
  EXPECT_EQ(p.kernels[0].launches, 2u);
  EXPECT_EQ(p.kernels[0].work_items, 4096u + 1u);
  EXPECT_EQ(p.width, parallel_width(d->info()));
  EXPECT_GT(p.wait_seconds, 0.0);
  EXPECT_LE(p.wait_seconds, p.wall_seconds);
  EXPECT_LE(p.narrow_seconds, p.device_seconds);
  EXPECT_EQ(p.narrow_seconds, p.kernels[0].narrow_seconds);
  EXPECT_TRUE(d->take_timings().empty());  // the meter took them
}

MV_INSTANTIATE_ON_ALL_DEVICES(ParallelismDeviceTest);

}  // namespace
}  // namespace mv::test
