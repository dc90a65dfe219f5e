// The segmented operations on every device vs plain loops: run boundaries, sums, scans within runs and arg-mins,
// on random runs, one run longer than a loop may run on lavapipe, single-element runs and ties; stream compaction.
#include <random>

#include "megavox/segmented.h"
#include "segmented_reference.h"
#include "test_support.h"

namespace mv::test {
namespace {

class SegmentedTest : public ::testing::TestWithParam<DeviceInfo> {};

// Sorted keys whose runs have random lengths up to max_run (max_run 0: one run of all n).
std::vector<uint64_t> run_keys(size_t n, uint32_t max_run, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<uint64_t> keys(n);
  uint64_t key = rng() >> 40;
  size_t left = 0;
  for (size_t i = 0; i < n; ++i) {
    if (max_run && left == 0) {
      key += 1 + (rng() & 7);
      left = 1 + rng() % max_run;
    }
    keys[i] = key;
    if (left) --left;
  }
  return keys;
}

template <class T>
std::vector<T> download_all(Device& dev, const Buffer& b, size_t count) {
  std::vector<T> out(count);
  if (count) dev.download(b, out.data(), count * sizeof(T));
  return out;
}

void check_case(Device& dev, const std::vector<uint64_t>& keys, uint32_t shift, uint64_t value_range, uint64_t seed) {
  const size_t n = keys.size();
  std::mt19937_64 rng(seed);
  std::vector<uint32_t> small(n);
  std::vector<uint64_t> wide(n);
  for (size_t i = 0; i < n; ++i) {
    small[i] = static_cast<uint32_t>(rng());
    wide[i] = value_range ? rng() % value_range : rng();
  }
  Buffer kb = dev.alloc(std::max<size_t>(n, 1) * 8, "keys");
  Buffer sb = dev.alloc(std::max<size_t>(n, 1) * 4, "values");
  Buffer wb = dev.alloc(std::max<size_t>(n, 1) * 8, "wide values");
  if (n) {
    dev.upload(kb, keys.data(), n * 8);
    dev.upload(sb, small.data(), n * 4);
    dev.upload(wb, wide.data(), n * 8);
  }
  dev.barrier();
  Segmentation seg = segment_by_key(dev, kb, n, shift);
  const std::vector<uint32_t> starts = ref::segment_starts(keys, shift);
  ASSERT_EQ(seg.count, starts.size() - 1) << "n = " << n;
  Buffer sums = dev.alloc(std::max<uint64_t>(seg.count, 1) * 8, "sums");
  Buffer scan = dev.alloc(std::max<size_t>(n, 1) * 8, "scan");
  Buffer arg = dev.alloc(std::max<uint64_t>(seg.count, 1) * 4, "argmin");
  segmented_sum(dev, seg, sb, sums);
  segmented_exclusive_scan(dev, seg, sb, scan);
  segmented_argmin(dev, seg, wb, arg);
  dev.finish();
  EXPECT_EQ(download_all<uint32_t>(dev, seg.starts, seg.count + 1), starts) << "n = " << n;
  EXPECT_EQ(download_all<uint64_t>(dev, sums, seg.count), ref::segmented_sum(small, starts)) << "n = " << n;
  EXPECT_EQ(download_all<uint64_t>(dev, scan, n), ref::segmented_exclusive_scan(small, starts)) << "n = " << n;
  EXPECT_EQ(download_all<uint32_t>(dev, arg, seg.count), ref::segmented_argmin(wide, starts)) << "n = " << n;
  if (n == 0) return;
  // Three planes over the same runs: plane k holds the values times k + 1 (wide enough to carry past 32 bits).
  std::vector<uint32_t> planes;
  for (uint32_t k = 0; k < 3; ++k)
    for (uint32_t v : small) planes.push_back(v * (k + 1));
  Buffer pb = dev.alloc(planes.size() * 4, "planes");
  dev.upload(pb, planes.data(), planes.size() * 4);
  Buffer psums = dev.alloc(3 * seg.count * 8, "plane sums");
  segmented_sum(dev, seg, pb, psums, 3);
  std::vector<uint64_t> want;
  for (uint32_t k = 0; k < 3; ++k) {
    const std::vector<uint32_t> plane(planes.begin() + k * n, planes.begin() + (k + 1) * n);
    const std::vector<uint64_t> one = ref::segmented_sum(plane, starts);
    want.insert(want.end(), one.begin(), one.end());
  }
  EXPECT_EQ(download_all<uint64_t>(dev, psums, 3 * seg.count), want) << "n = " << n;
}

TEST_P(SegmentedTest, RandomRunsMatchTheReference) {
  Device& dev = shared_device(GetParam());
  for (size_t n : {size_t{0}, size_t{1}, size_t{2}, size_t{255}, size_t{4097}, size_t{100003}})
    for (uint32_t max_run : {1u, 3u, 50u, 5000u}) check_case(dev, run_keys(n, max_run, n + max_run), 0, 0, n);
}

// Ties: the first of equal values wins, within a block and across blocks.
TEST_P(SegmentedTest, TiesPickTheFirst) {
  Device& dev = shared_device(GetParam());
  check_case(dev, run_keys(70001, 9000, 3), 0, 2, 4);
  check_case(dev, run_keys(70001, 40, 5), 0, 1, 6);
}

// One run longer than lavapipe lets one loop run, spread over many blocks, and runs by shifted keys.
TEST_P(SegmentedTest, LongRunsAndShiftedKeys) {
  Device& dev = shared_device(GetParam());
  check_case(dev, run_keys(200003, 0, 7), 0, 0, 8);
  check_case(dev, run_keys(200003, 0, 9), 0, 1000, 10);
  std::vector<uint64_t> keys = run_keys(150001, 2, 11);
  check_case(dev, keys, 9, 0, 12);
  check_case(dev, keys, 64, 50, 13);
}

// Stream compaction: the flagged positions in order, then n, against a plain loop; none, all, sparse and dense.
TEST_P(SegmentedTest, SelectFlaggedListsTheFlaggedPositionsInOrder) {
  Device& dev = shared_device(GetParam());
  std::mt19937_64 rng(21);
  for (size_t n : {size_t{0}, size_t{1}, size_t{7}, size_t{4097}, size_t{300007}})
    for (uint32_t every : {0u, 1u, 2u, 97u}) {  // 0: no flag; k: about one in k (1: all)
      std::vector<uint32_t> flags(n);
      for (uint32_t& f : flags) f = every && rng() % every == 0 ? 1u : 0u;
      std::vector<uint32_t> want;
      for (size_t i = 0; i < n; ++i)
        if (flags[i]) want.push_back(static_cast<uint32_t>(i));
      want.push_back(static_cast<uint32_t>(n));
      Buffer fb = dev.alloc(std::max<size_t>(n, 1) * 4, "flags");
      Buffer pb = dev.alloc((n + 1) * 4, "positions");
      if (n) dev.upload(fb, flags.data(), n * 4);
      const uint64_t count = select_flagged(dev, fb, pb, n);
      ASSERT_EQ(count, want.size() - 1) << "n = " << n << ", one in " << every;
      EXPECT_EQ(download_all<uint32_t>(dev, pb, want.size()), want) << "n = " << n << ", one in " << every;
    }
}

MV_INSTANTIATE_ON_ALL_DEVICES(SegmentedTest);

}  // namespace
}  // namespace mv::test
