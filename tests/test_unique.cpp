// Unique of sorted 64-bit keys on every device vs the reference: device buffers, and host arrays in chunks.
#include <algorithm>

#include "primitives/chunking.h"
#include "reference.h"
#include "megavox/primitives.h"
#include "test_support.h"

namespace mv::test {
namespace {

class UniqueTest : public ::testing::TestWithParam<DeviceInfo> {
 protected:
  Device& dev() { return shared_device(GetParam()); }

  // Sorted keys of `n` draws from `range` values: many repeats when range is small.
  static std::vector<uint64_t> sorted_draws(size_t n, uint64_t range, uint64_t seed) {
    std::vector<uint64_t> keys = random_u64(n, seed);
    for (auto& k : keys) k = (k % range) * 0x9e3779b97f4a7c15ull;  // spread over all 64 bits
    std::sort(keys.begin(), keys.end());
    return keys;
  }
};

TEST_P(UniqueTest, DeviceBuffersMatchReference) {
  for (size_t n : {size_t{1}, size_t{2}, size_t{255}, size_t{4099}, (size_t{1} << 20) + 3}) {
    for (uint64_t range : {uint64_t{1}, uint64_t{3}, uint64_t{n / 2 + 1}, uint64_t{1} << 62}) {
      std::vector<uint64_t> keys = sorted_draws(n, range, n + range);
      std::vector<uint64_t> expect = ref::unique_sorted(keys);
      Buffer kb = dev().alloc(n * 8, "unique keys");
      Buffer out = dev().alloc(n * 8, "unique output");
      dev().upload(kb, keys.data(), n * 8);
      uint64_t m = unique_sorted(dev(), kb, out, n);
      ASSERT_EQ(m, expect.size()) << "n = " << n << ", range = " << range;
      std::vector<uint64_t> got(m);
      dev().download(out, got.data(), m * 8);
      ASSERT_EQ(got, expect) << "n = " << n << ", range = " << range;
    }
  }
}

TEST_P(UniqueTest, EmptyInputIsZero) {
  Buffer none = dev().alloc(8, "keys");
  EXPECT_EQ(unique_sorted(dev(), none, none, 0), 0u);
}

// Host arrays through the chunked path with small chunks, over keys whose runs meet the seams in every way:
// a repeat across a seam, runs of one key over several chunks (the whole input one key, too), runs that end
// right at a seam, chunks of one key; out of place and in place.
TEST_P(UniqueTest, HostArraysInChunksDropSeamRepeats) {
  const std::vector<uint64_t> crafted = {1, 1, 1, 1, 2, 2, 2, 2, 2, 3, 4, 4, 5, 6, 6, 6, 6, 6, 6, 6, 6, 7};
  for (uint64_t chunk : {1u, 2u, 3u, 4u, 5u, 64u, 5000u}) {
    const size_t n = chunk <= 5 ? 30 * chunk : 3001;  // about 30 chunks or more (a device call each)
    std::vector<std::vector<uint64_t>> inputs = {crafted};
    for (uint64_t range : {uint64_t{1}, uint64_t{2}, uint64_t{7}, uint64_t{n / 3}, uint64_t{1} << 62})
      inputs.push_back(sorted_draws(n, range, chunk * 31 + range));
    for (const auto& keys : inputs) {
      SCOPED_TRACE("chunk " + std::to_string(chunk) + ", " + std::to_string(keys.size()) + " keys");
      std::vector<uint64_t> expect = ref::unique_sorted(keys);
      std::vector<uint64_t> got(keys.size(), 0xdeadbeef);
      ASSERT_EQ(detail::unique_sorted_chunked(dev(), keys, got, chunk), expect.size());
      got.resize(expect.size());
      ASSERT_EQ(got, expect);
      std::vector<uint64_t> in_place = keys;
      in_place.resize(detail::unique_sorted_chunked(dev(), in_place, in_place, chunk));
      ASSERT_EQ(in_place, expect);
    }
  }
}

// The public overload picks its chunk from the device's memory: here 8 MiB of keys over a 4 MiB budget.
TEST_P(UniqueTest, HostArraysChunkedByTheBudget) {
  auto small = Device::open({GetParam().selector(), 4u << 20, false});
  std::vector<uint64_t> keys = sorted_draws(size_t{1} << 20, 300000, 5);
  ASSERT_LT(detail::device_chunk(*small, "unique", 20, 8), keys.size());  // several chunks
  std::vector<uint64_t> expect = ref::unique_sorted(keys);
  std::vector<uint64_t> got(keys.size());
  got.resize(unique_sorted(*small, keys, got));
  EXPECT_EQ(got, expect);
  EXPECT_EQ(unique_sorted(*small, std::span<const uint64_t>(), std::span<uint64_t>()), 0u);
  std::string msg = error_message([&] { unique_sorted(*small, keys, std::span<uint64_t>(got).first(1)); });
  EXPECT_NE(msg.find("fewer than"), std::string::npos) << msg;
}

TEST_P(UniqueTest, OneDeviceCallIsCappedAtMaxDeviceItems) {
  Buffer small = dev().alloc(8, "keys");
  std::string msg = error_message([&] { unique_sorted(dev(), small, small, kMaxDeviceItems + 1); });
  EXPECT_NE(msg.find(std::to_string(kMaxDeviceItems)), std::string::npos) << msg;
}

MV_INSTANTIATE_ON_ALL_DEVICES(UniqueTest);

}  // namespace
}  // namespace mv::test
