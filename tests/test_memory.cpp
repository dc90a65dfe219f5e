// The device memory budget and page pool.
#include <algorithm>
#include <cstring>
#include <vector>

#include "megavox/error.h"
#include "test_support.h"

namespace mv::test {
namespace {

class MemoryTest : public ::testing::TestWithParam<DeviceInfo> {};

TEST_P(MemoryTest, RequestBeyondBudgetNamesWhatAndWhatIsLeft) {
  auto dev = Device::open({GetParam().selector(), 4u << 20, false});
  EXPECT_EQ(dev->memory_budget(), 4u << 20);
  Buffer a = dev->alloc(3u << 20, "first array");
  try {
    Buffer b = dev->alloc(2u << 20, "second array");
    FAIL() << "expected a budget error";
  } catch (const Error& e) {
    std::string msg = e.what();
    EXPECT_NE(msg.find("second array needs 2.0 MiB"), std::string::npos) << msg;
    EXPECT_NE(msg.find("1.0 MiB left"), std::string::npos) << msg;
    EXPECT_NE(msg.find("budget 4.0 MiB"), std::string::npos) << msg;
  }
  EXPECT_EQ(dev->memory_used(), 3u << 20);
}

TEST_P(MemoryTest, ReleasedPagesAreReused) {
  auto dev = Device::open({GetParam().selector(), 4u << 20, false});
  for (int i = 0; i < 20; ++i) {
    Buffer a = dev->alloc(3u << 20, "array");  // fits only if the previous one's pages came back
    dev->fill(a, 7, 3u << 20);
  }
  dev->finish();
  EXPECT_EQ(dev->memory_used(), 0u);
}

// trim() gives back only storage that holds no buffer: a live buffer keeps its contents, the budget is whole
// again afterwards, and allocations after it work (in a new arena).
TEST_P(MemoryTest, TrimFreesOnlyEmptyStorage) {
  auto dev = Device::open({GetParam().selector(), 8u << 20, false});
  {
    Buffer a = dev->alloc(3u << 20, "released before the trim");
    dev->fill(a, 1, 3u << 20);
  }
  Buffer kept = dev->alloc(4096, "kept across the trim");
  dev->fill(kept, 0x5eed, 4096);
  dev->trim();
  uint32_t v = 0;
  dev->download(kept, &v, 4, 4092);
  EXPECT_EQ(v, 0x5eedu);
  EXPECT_EQ(dev->memory_used(), dev->page_bytes());
  kept = Buffer();
  dev->trim();
  EXPECT_EQ(dev->memory_used(), 0u);
  for (int i = 0; i < 3; ++i) {  // the whole budget again, each time in storage made anew
    Buffer b = dev->alloc(7u << 20, "after the trim");
    dev->fill(b, static_cast<uint32_t>(i), 7u << 20);
    dev->download(b, &v, 4, (7u << 20) - 4);
    EXPECT_EQ(v, static_cast<uint32_t>(i));
    b = Buffer();
    dev->trim();
  }
}

// A CPU device's buffers can be read in place: after finish(), host_view holds what the device wrote (here a
// fill and a copy), the same bytes as a download. Other devices have no view.
TEST_P(MemoryTest, HostViewShowsWhatTheDeviceWrote) {
  auto dev = Device::open({GetParam().selector(), 8u << 20, false});
  Buffer a = dev->alloc(1u << 20, "filled");
  Buffer b = dev->alloc(1u << 20, "copied");
  dev->fill(a, 0xa5a5a5a5u, 1u << 20);
  dev->fill(a, 0x01020304u, 4096, 8192);
  dev->barrier();
  dev->copy(a, b, 1u << 20);
  dev->finish();
  const void* view = dev->host_view(b);
  if (GetParam().type != "cpu") {
    EXPECT_EQ(view, nullptr);
    return;
  }
  ASSERT_NE(view, nullptr);
  std::vector<uint8_t> down(1u << 20);
  dev->download(b, down.data(), down.size());
  EXPECT_EQ(std::memcmp(view, down.data(), down.size()), 0);
  uint32_t word = 0;
  std::memcpy(&word, static_cast<const uint8_t*>(view) + 8192, 4);
  EXPECT_EQ(word, 0x01020304u);
  EXPECT_EQ(dev->host_view(Buffer()), nullptr);
}

TEST_P(MemoryTest, SmallBuffersSharePagesOfOneArena) {
  auto dev = Device::open({GetParam().selector(), 8u << 20, false});
  std::vector<Buffer> bufs;
  for (int i = 0; i < 50; ++i) bufs.push_back(dev->alloc(1000 + i, "small"));
  EXPECT_EQ(dev->memory_used(), 50 * dev->page_bytes());
  // Each buffer keeps its own contents.
  for (int i = 0; i < 50; ++i) dev->fill(bufs[i], static_cast<uint32_t>(i), 1000);
  dev->finish();
  for (int i = 0; i < 50; ++i) {
    uint32_t v = 0;
    dev->download(bufs[i], &v, 4, 996);
    ASSERT_EQ(v, static_cast<uint32_t>(i));
  }
}

TEST_P(MemoryTest, BudgetLargerThanTheDeviceIsAnError) {
  EXPECT_THROW(Device::open({GetParam().selector(), GetParam().global_memory_bytes + (1ull << 30), false}), Error);
  EXPECT_THROW(Device::open({GetParam().selector(), 1000, false}), Error);  // smaller than one page
}

TEST_P(MemoryTest, ArrayLargerThanOneAllocationIsAClearError) {
  auto dev = Device::open({GetParam().selector(), 0, false});
  // Beyond one allocation and the budget whatever the device reports (PoCL's sizes follow the free RAM).
  const uint64_t huge = std::max<uint64_t>(GetParam().max_allocation_bytes, dev->memory_budget()) + (uint64_t{1} << 30);
  try {
    dev->alloc(huge, "huge array");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("huge array needs"), std::string::npos) << e.what();
  }
}

MV_INSTANTIATE_ON_ALL_DEVICES(MemoryTest);

}  // namespace
}  // namespace mv::test
