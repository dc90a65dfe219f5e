// Morton encoding on every device vs the bit-by-bit reference.
#include "reference.h"
#include "megavox/primitives.h"
#include "test_support.h"

namespace mv::test {
namespace {

class MortonTest : public ::testing::TestWithParam<DeviceInfo> {};

std::vector<uint32_t> test_points() {
  std::vector<uint32_t> xyz = random_u32(3 * 100003, 11);  // random, including bits above the key range
  const uint32_t edges[] = {0u, 1u, 1023u, 1024u, (1u << 21) - 1, 1u << 21, 0xffffffffu};
  for (uint32_t x : edges)
    for (uint32_t y : edges)
      for (uint32_t z : edges) xyz.insert(xyz.end(), {x, y, z});
  return xyz;
}

TEST_P(MortonTest, MatchesReference) {
  Device& dev = shared_device(GetParam());
  std::vector<uint32_t> xyz = test_points();
  const uint32_t n = static_cast<uint32_t>(xyz.size() / 3);
  Buffer points = dev.alloc(xyz.size() * 4, "points");
  dev.upload(points, xyz.data(), xyz.size() * 4);
  Buffer k64 = dev.alloc(uint64_t{n} * 8, "keys64");
  Buffer k32 = dev.alloc(uint64_t{n} * 4, "keys32");
  morton_encode(dev, points, k64, n, KeyBits::k64);
  morton_encode(dev, points, k32, n, KeyBits::k32);
  dev.finish();
  std::vector<uint64_t> got64(n);
  std::vector<uint32_t> got32(n);
  dev.download(k64, got64.data(), uint64_t{n} * 8);
  dev.download(k32, got32.data(), uint64_t{n} * 4);
  for (uint32_t i = 0; i < n; ++i) {
    ASSERT_EQ(got64[i], ref::morton3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], 21)) << "point " << i;
    ASSERT_EQ(got32[i], ref::morton3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], 10)) << "point " << i;
  }
}

TEST_P(MortonTest, EmptyInputIsANoOp) {
  Device& dev = shared_device(GetParam());
  Buffer points = dev.alloc(12, "points");
  Buffer keys = dev.alloc(8, "keys");
  dev.fill(keys, 0xabababab, 8);
  morton_encode(dev, points, keys, 0, KeyBits::k64);
  dev.finish();
  uint64_t k = 0;
  dev.download(keys, &k, 8);
  EXPECT_EQ(k, 0xababababababababull);
}

TEST_P(MortonTest, OneDeviceCallIsCappedAtMaxDeviceItems) {
  Device& dev = shared_device(GetParam());
  Buffer points = dev.alloc(12, "points");
  Buffer keys = dev.alloc(8, "keys");
  std::string msg = error_message([&] { morton_encode(dev, points, keys, kMaxDeviceItems + 1, KeyBits::k64); });
  EXPECT_NE(msg.find(std::to_string(kMaxDeviceItems)), std::string::npos) << msg;
}

MV_INSTANTIATE_ON_ALL_DEVICES(MortonTest);

}  // namespace
}  // namespace mv::test
