// Exclusive scan on every device vs the reference: 32-bit sums, exact 64-bit sums, and host arrays in chunks.
#include "primitives/chunking.h"
#include "reference.h"
#include "megavox/primitives.h"
#include "test_support.h"

namespace mv::test {
namespace {

class ScanTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST_P(ScanTest, MatchesReference) {
  Device& dev = shared_device(GetParam());
  for (size_t n : {size_t{0}, size_t{1}, size_t{255}, size_t{257}, size_t{4099}, (size_t{1} << 20) + 3}) {
    std::vector<uint32_t> in = random_u32(n, n);
    for (auto& v : in) v &= 0xffff;  // totals stay below 2^32
    std::vector<uint32_t> expect = ref::exclusive_scan(in);
    Buffer src = dev.alloc(std::max<size_t>(n, 1) * 4, "scan input");
    Buffer dst = dev.alloc((n + 1) * 4, "scan output");
    dev.upload(src, in.data(), n * 4);
    dev.fill(dst, 0xdeadbeef, (n + 1) * 4);
    dev.barrier();
    exclusive_scan(dev, src, dst, static_cast<uint32_t>(n));
    dev.finish();
    std::vector<uint32_t> got(n + 1);
    dev.download(dst, got.data(), (n + 1) * 4);
    ASSERT_EQ(got, expect) << "n = " << n;
  }
}

TEST_P(ScanTest, InPlace) {
  Device& dev = shared_device(GetParam());
  std::vector<uint32_t> in = random_u32(100000, 5);
  for (auto& v : in) v &= 0xff;
  std::vector<uint32_t> expect = ref::exclusive_scan(in);
  Buffer buf = dev.alloc((in.size() + 1) * 4, "scan data");
  dev.upload(buf, in.data(), in.size() * 4);
  exclusive_scan(dev, buf, buf, static_cast<uint32_t>(in.size()));
  dev.finish();
  std::vector<uint32_t> got(in.size() + 1);
  dev.download(buf, got.data(), got.size() * 4);
  EXPECT_EQ(got, expect);
}

// 32-bit sums wrap as 32-bit arithmetic does, though the block sums under them are 64-bit.
TEST_P(ScanTest, NarrowSumsWrapMod2To32) {
  Device& dev = shared_device(GetParam());
  std::vector<uint32_t> in = random_u32((size_t{1} << 20) + 3, 17);
  std::vector<uint32_t> expect = ref::exclusive_scan(in);
  Buffer buf = dev.alloc((in.size() + 1) * 4, "scan data");
  dev.upload(buf, in.data(), in.size() * 4);
  exclusive_scan(dev, buf, buf, in.size());
  std::vector<uint32_t> got(in.size() + 1);
  dev.download(buf, got.data(), got.size() * 4);
  EXPECT_EQ(got, expect);
}

// Exact sums of full-range values (totals near 2^52), from 0 and from a start past 2^32.
TEST_P(ScanTest, Wide64MatchesReference) {
  Device& dev = shared_device(GetParam());
  for (size_t n : {size_t{0}, size_t{1}, size_t{255}, size_t{4099}, (size_t{1} << 20) + 3}) {
    for (uint64_t start : {uint64_t{0}, (uint64_t{5} << 32) + 7}) {
      std::vector<uint32_t> in = random_u32(n, n + 1);
      std::vector<uint64_t> expect = ref::exclusive_scan64(in, start);
      Buffer src = dev.alloc(std::max<size_t>(n, 1) * 4, "scan input");
      Buffer dst = dev.alloc((n + 1) * 8, "scan output");
      dev.upload(src, in.data(), n * 4);
      dev.fill(dst, 0xdeadbeef, (n + 1) * 8);
      dev.barrier();
      exclusive_scan64(dev, src, dst, n, start);
      std::vector<uint64_t> got(n + 1);
      dev.download(dst, got.data(), (n + 1) * 8);
      ASSERT_EQ(got, expect) << "n = " << n << ", start = " << start;
    }
  }
}

// Host arrays through the chunked path with small chunks: seams after every value, every few values, and none
// (one chunk larger than the input); the running total passes 2^32 within the first chunks and is carried on.
TEST_P(ScanTest, HostArraysInChunksCarry64BitTotals) {
  Device& dev = shared_device(GetParam());
  for (uint64_t chunk : {1u, 2u, 3u, 7u, 64u, 1000u, 5000u}) {
    const size_t n = chunk <= 3 ? 200 : 3001;
    std::vector<uint32_t> in = random_u32(n, chunk);
    for (size_t i = 0; i < n; i += 3) in[i] = i % 2 ? 0u : 0xffffffffu;  // zeros and maxima at seams too
    std::vector<uint64_t> expect = ref::exclusive_scan64(in);
    std::vector<uint64_t> got(n + 1, 0xdeadbeef);
    uint64_t total = detail::exclusive_scan_chunked(dev, in, got, chunk);
    ASSERT_EQ(got, expect) << "chunk = " << chunk;
    EXPECT_EQ(total, expect.back());
    EXPECT_GT(total, uint64_t{1} << 36);
  }
}

// The public overload picks its chunk from the device's memory: on a small budget the input spans many chunks.
TEST_P(ScanTest, HostArraysChunkedByTheBudget) {
  auto small = Device::open({GetParam().selector(), 4u << 20, false});
  std::vector<uint32_t> in = random_u32((size_t{1} << 20) + 3, 23);
  ASSERT_LT(detail::device_chunk(*small, "scan", 12, 8), in.size());  // several chunks
  std::vector<uint64_t> got(in.size() + 1);
  EXPECT_EQ(exclusive_scan(*small, in, got), ref::exclusive_scan64(in).back());
  EXPECT_EQ(got, ref::exclusive_scan64(in));
  std::vector<uint64_t> one(1, 7);
  EXPECT_EQ(exclusive_scan(*small, std::span<const uint32_t>(), one), 0u);
  EXPECT_EQ(one[0], 0u);
  std::string msg = error_message([&] { exclusive_scan(*small, in, one); });
  EXPECT_NE(msg.find("not n + 1"), std::string::npos) << msg;
}

TEST_P(ScanTest, OneDeviceCallIsCappedAtMaxDeviceItems) {
  Device& dev = shared_device(GetParam());
  Buffer small = dev.alloc(8, "scan data");
  std::string msg = error_message([&] { exclusive_scan(dev, small, small, kMaxDeviceItems + 1); });
  EXPECT_NE(msg.find(std::to_string(kMaxDeviceItems)), std::string::npos) << msg;
}

MV_INSTANTIATE_ON_ALL_DEVICES(ScanTest);

}  // namespace
}  // namespace mv::test
