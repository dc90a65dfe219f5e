// Unique of sorted 64-bit keys on every device vs the reference.
#include <algorithm>

#include "host/ref/reference.h"
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

TEST_P(UniqueTest, OneDeviceCallIsCappedAtMaxDeviceItems) {
  Buffer small = dev().alloc(8, "keys");
  std::string msg = error_message([&] { unique_sorted(dev(), small, small, kMaxDeviceItems + 1); });
  EXPECT_NE(msg.find(std::to_string(kMaxDeviceItems)), std::string::npos) << msg;
}

MV_INSTANTIATE_ON_ALL_DEVICES(UniqueTest);

}  // namespace
}  // namespace mv::test
