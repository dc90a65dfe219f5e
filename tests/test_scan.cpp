// Exclusive scan on every device vs the reference.
#include "host/ref/reference.h"
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

TEST_P(ScanTest, OneDeviceCallIsCappedAtMaxDeviceItems) {
  Device& dev = shared_device(GetParam());
  Buffer small = dev.alloc(8, "scan data");
  std::string msg = error_message([&] { exclusive_scan(dev, small, small, kMaxDeviceItems + 1); });
  EXPECT_NE(msg.find(std::to_string(kMaxDeviceItems)), std::string::npos) << msg;
}

MV_INSTANTIATE_ON_ALL_DEVICES(ScanTest);

}  // namespace
}  // namespace mv::test
