// The page pool on its own, over a fake backend that keeps arenas in host memory and counts them: the
// budget, page rounding, arenas capped at the largest allocation, first fit and fragmentation, retired
// ranges, exhaustion and recovery, and a backend that cannot create an arena. No device is needed.
#include <gtest/gtest.h>

#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "megavox/error.h"
#include "memory_pool.h"

namespace mv::test {
namespace {

constexpr uint64_t kPage = 4096;

// Arenas are host memory; the pool uses nothing else but finish(), which is counted. The rest throws.
class CountingBackend : public rt::Backend {
 public:
  struct HostArena : rt::BackendArena {
    HostArena(CountingBackend& backend, uint64_t bytes) : owner(backend), memory(bytes) { ++owner.live_arenas; }
    ~HostArena() override { --owner.live_arenas; }
    CountingBackend& owner;
    std::vector<std::byte> memory;
  };

  CountingBackend() { info_.name = "fake device"; }

  const DeviceInfo& info() const override { return info_; }
  std::unique_ptr<rt::BackendArena> create_arena(uint64_t bytes) override {
    if (fail_arenas) throw Error("fake device: cannot allocate " + format_bytes(bytes));
    arena_bytes.push_back(bytes);
    bytes_created += bytes;
    return std::make_unique<HostArena>(*this, bytes);
  }
  std::unique_ptr<rt::BackendBuffer> create_buffer(rt::BackendArena&, uint64_t, uint64_t) override { unused(); }
  void upload(rt::BackendBuffer&, uint64_t, const void*, uint64_t) override { unused(); }
  void download(rt::BackendBuffer&, uint64_t, void*, uint64_t) override { unused(); }
  void upload_async(rt::BackendBuffer&, uint64_t, const void*, uint64_t) override { unused(); }
  void fill(rt::BackendBuffer&, uint64_t, uint64_t, uint32_t) override { unused(); }
  void copy(rt::BackendBuffer&, uint64_t, rt::BackendBuffer&, uint64_t, uint64_t) override { unused(); }
  rt::BackendKernel& kernel(const rt::KernelDesc&) override { unused(); }
  void dispatch(rt::BackendKernel&, const LaunchGrid&, std::span<rt::BackendBuffer* const>, const void*,
                size_t) override {
    unused();
  }
  void barrier() override {}
  uint64_t submit() override { unused(); }
  void wait(uint64_t) override { unused(); }
  void finish() override { ++finishes; }
  void set_profiling(bool) override {}
  std::vector<KernelTiming> take_timings() override { return {}; }

  size_t arenas_created() const { return arena_bytes.size(); }

  std::vector<uint64_t> arena_bytes;  // of each arena created, in order
  uint64_t bytes_created = 0;
  int live_arenas = 0;
  int finishes = 0;
  bool fail_arenas = false;

 private:
  [[noreturn]] static void unused() { throw std::logic_error("the memory pool does not use this"); }
  DeviceInfo info_;
};

using Range = rt::MemoryPool::Range;

// The message of the error `allocate` throws (mv::DeviceMemoryError), or "" with a test failure when none is.
std::string allocation_error(rt::MemoryPool& pool, uint64_t bytes, const std::string& what) {
  try {
    pool.allocate(bytes, what);
  } catch (const DeviceMemoryError& e) {
    return e.what();
  }
  ADD_FAILURE() << what << " (" << bytes << " bytes) was placed";
  return "";
}

bool overlap(const Range& a, const Range& b) {
  return a.arena == b.arena && a.first_page < b.first_page + b.pages && b.first_page < a.first_page + a.pages;
}

TEST(MemoryPool, AllocationsUpToTheBudgetSucceedAndTheNextNamesWhatAndWhatIsLeft) {
  CountingBackend backend;
  rt::MemoryPool pool(backend, 16 * kPage, kPage, 16 * kPage);
  std::vector<Range> held;
  for (int i = 0; i < 4; ++i) held.push_back(pool.allocate(4 * kPage, "quarter"));
  for (size_t i = 0; i < held.size(); ++i)
    for (size_t j = 0; j < i; ++j) EXPECT_FALSE(overlap(held[i], held[j])) << i << " and " << j;
  EXPECT_EQ(pool.used(), pool.budget());
  const std::string msg = allocation_error(pool, 100, "one more array");
  EXPECT_NE(msg.find("one more array needs 100 B"), std::string::npos) << msg;
  EXPECT_NE(msg.find("more than the budget has left"), std::string::npos) << msg;
  EXPECT_NE(msg.find("budget 64.0 KiB, 0 B left"), std::string::npos) << msg;
  EXPECT_NE(msg.find("raise the device memory budget"), std::string::npos) << msg;
  EXPECT_EQ(pool.used(), pool.budget());  // a failed request changes nothing
  EXPECT_EQ(backend.finishes, 0);         // nothing was retired, so nothing to wait for
  EXPECT_EQ(backend.arenas_created(), 1u);
}

TEST(MemoryPool, RequestOverTheWholeBudgetIsRefusedUpFront) {
  CountingBackend backend;
  rt::MemoryPool pool(backend, 8 * kPage, kPage, 8 * kPage);
  const std::string msg = allocation_error(pool, 8 * kPage + 1, "huge array");
  EXPECT_NE(msg.find("huge array needs 32.0 KiB, more than the whole budget"), std::string::npos) << msg;
  EXPECT_NE(msg.find("32.0 KiB left"), std::string::npos) << msg;
  EXPECT_EQ(backend.arenas_created(), 0u);
}

TEST(MemoryPool, RequestsAreRoundedUpToWholePages) {
  CountingBackend backend;
  rt::MemoryPool pool(backend, 64 * kPage, kPage, 64 * kPage);
  const std::pair<uint64_t, uint64_t> bytes_pages[] = {{0, 1}, {1, 1}, {kPage, 1}, {kPage + 1, 2}, {5 * kPage - 1, 5}};
  uint64_t pages = 0;
  for (auto [bytes, expect] : bytes_pages) {
    Range r = pool.allocate(bytes, "array");
    EXPECT_EQ(r.pages, expect) << bytes << " bytes";
    EXPECT_EQ(r.first_page, pages) << bytes << " bytes";  // first fit: one after another
    pages += expect;
    EXPECT_EQ(pool.used(), pages * kPage);
  }
}

TEST(MemoryPool, BudgetAndArenaCapAreWholePages) {
  CountingBackend backend;
  rt::MemoryPool pool(backend, 10 * kPage + 100, kPage, 3 * kPage + 5);
  EXPECT_EQ(pool.budget(), 10 * kPage);
  EXPECT_EQ(pool.max_arena_bytes(), 3 * kPage);
  rt::MemoryPool capped(backend, 4 * kPage, kPage, 1000 * kPage);  // no arena beyond the budget
  EXPECT_EQ(capped.max_arena_bytes(), 4 * kPage);
  EXPECT_THROW(rt::MemoryPool tiny(backend, kPage - 1, kPage, kPage), Error);  // smaller than one page
  EXPECT_EQ(backend.arenas_created(), 0u);  // arenas come on demand
}

TEST(MemoryPool, ArenasAreCappedAtTheLargestAllocation) {
  CountingBackend backend;
  rt::MemoryPool pool(backend, 40 * kPage, kPage, 16 * kPage);
  for (int i = 0; i < 16; ++i) EXPECT_EQ(pool.allocate(kPage, "page").arena, 0u);
  EXPECT_EQ(backend.arenas_created(), 1u);
  Range next = pool.allocate(kPage, "page");  // the first arena is full: a second one
  EXPECT_EQ(next.arena, 1u);
  EXPECT_EQ(next.first_page, 0u);
  Range rest = pool.allocate(15 * kPage, "rest");
  EXPECT_EQ(rest.arena, 1u);
  Range last = pool.allocate(8 * kPage, "last");  // the last arena is what the budget has left
  EXPECT_EQ(last.arena, 2u);
  EXPECT_EQ(backend.arena_bytes, (std::vector<uint64_t>{16 * kPage, 16 * kPage, 8 * kPage}));
  EXPECT_EQ(backend.bytes_created, pool.budget());
  EXPECT_EQ(pool.used(), pool.budget());
  for (uint32_t a = 0; a < 3; ++a)  // the arenas handed out are the backend's
    EXPECT_EQ(static_cast<CountingBackend::HostArena&>(pool.arena(a)).memory.size(), backend.arena_bytes[a]);

  // More than one arena may hold is refused, naming the device and the cap.
  rt::MemoryPool other(backend, 40 * kPage, kPage, 16 * kPage);
  const std::string msg = allocation_error(other, 17 * kPage, "long array");
  EXPECT_NE(msg.find("more than one allocation may hold on fake device (64.0 KiB)"), std::string::npos) << msg;
}

TEST(MemoryPool, ArenasLiveAsLongAsThePool) {
  CountingBackend backend;
  {
    rt::MemoryPool pool(backend, 8 * kPage, kPage, 4 * kPage);
    Range a = pool.allocate(4 * kPage, "a");
    pool.allocate(4 * kPage, "b");
    EXPECT_EQ(backend.live_arenas, 2);
    pool.release(a);
    pool.reclaim();  // pages come back; the arena stays
    EXPECT_EQ(backend.live_arenas, 2);
    EXPECT_EQ(pool.allocate(kPage, "c").arena, 0u);
    EXPECT_EQ(backend.arenas_created(), 2u);
  }
  EXPECT_EQ(backend.live_arenas, 0);
}

// Sixteen single pages with every other one released: half the arena is free, in runs of one page.
void fragment(rt::MemoryPool& pool, std::vector<Range>& kept) {
  for (int i = 0; i < 16; ++i) {
    Range r = pool.allocate(kPage, "page");
    if (i % 2) kept.push_back(r);
    else pool.release(r);
  }
  pool.reclaim();
}

TEST(MemoryPool, FragmentedArenaWithNoBudgetLeftRefusesARunItCannotHold) {
  CountingBackend backend;
  rt::MemoryPool pool(backend, 16 * kPage, kPage, 16 * kPage);
  std::vector<Range> kept;
  fragment(pool, kept);
  EXPECT_EQ(pool.used(), 8 * kPage);
  const std::string msg = allocation_error(pool, 2 * kPage, "two pages");
  EXPECT_NE(msg.find("no free run of pages is large enough"), std::string::npos) << msg;
  EXPECT_NE(msg.find("32.0 KiB left, largest free run 4.0 KiB"), std::string::npos) << msg;
  EXPECT_EQ(backend.arenas_created(), 1u);
  // Single pages still fit, first fit from the start.
  for (uint64_t p = 0; p < 16; p += 2) {
    Range r = pool.allocate(kPage, "page");
    EXPECT_EQ(r.arena, 0u);
    EXPECT_EQ(r.first_page, p);
  }
  EXPECT_EQ(pool.used(), pool.budget());
}

TEST(MemoryPool, FragmentedArenaWithBudgetLeftPlacesTheRunInANewArena) {
  CountingBackend backend;
  rt::MemoryPool pool(backend, 32 * kPage, kPage, 16 * kPage);
  std::vector<Range> kept;
  fragment(pool, kept);
  Range r = pool.allocate(2 * kPage, "two pages");
  EXPECT_EQ(r.arena, 1u);
  EXPECT_EQ(r.first_page, 0u);
  EXPECT_EQ(backend.arenas_created(), 2u);
  EXPECT_EQ(pool.allocate(kPage, "page").arena, 0u);  // a page still goes to the first hole
}

TEST(MemoryPool, FirstFitTakesTheFirstRunLongEnough) {
  CountingBackend backend;
  rt::MemoryPool pool(backend, 16 * kPage, kPage, 16 * kPage);
  std::vector<Range> r;
  for (uint64_t pages : {1, 1, 3, 1, 2, 8}) r.push_back(pool.allocate(pages * kPage, "array"));
  pool.release(r[0]);  // free: page 0, pages 2-4, pages 6-7
  pool.release(r[2]);
  pool.release(r[4]);
  pool.reclaim();
  EXPECT_EQ(pool.allocate(2 * kPage, "two").first_page, 2u);
  EXPECT_EQ(pool.allocate(2 * kPage, "two").first_page, 6u);
  EXPECT_EQ(pool.allocate(kPage, "one").first_page, 0u);
  EXPECT_EQ(pool.allocate(kPage, "one").first_page, 4u);
  EXPECT_EQ(pool.used(), pool.budget());
}

TEST(MemoryPool, RetiredRangesAreNotReusedUntilReclaimed) {
  CountingBackend backend;
  rt::MemoryPool pool(backend, 8 * kPage, kPage, 8 * kPage);
  Range a = pool.allocate(4 * kPage, "a");
  pool.release(a);
  EXPECT_EQ(pool.used(), 4 * kPage);  // retired pages still count: recorded work may use them
  Range b = pool.allocate(4 * kPage, "b");
  EXPECT_EQ(b.first_page, 4u);  // not a's pages
  EXPECT_EQ(backend.finishes, 0);
  pool.reclaim();
  EXPECT_EQ(pool.used(), 4 * kPage);
  EXPECT_EQ(pool.allocate(4 * kPage, "c").first_page, 0u);
  EXPECT_EQ(backend.finishes, 0);
}

TEST(MemoryPool, ExhaustedPoolWaitsForRetiredPagesRatherThanFailing) {
  CountingBackend backend;
  rt::MemoryPool pool(backend, 8 * kPage, kPage, 8 * kPage);
  Range a = pool.allocate(4 * kPage, "a"), b = pool.allocate(4 * kPage, "b");
  pool.release(a);
  pool.release(b);
  Range c = pool.allocate(8 * kPage, "c");  // only fits once the device is idle and the retired pages are back
  EXPECT_EQ(backend.finishes, 1);
  EXPECT_EQ(c.first_page, 0u);
  EXPECT_EQ(pool.used(), 8 * kPage);
  EXPECT_EQ(backend.arenas_created(), 1u);
}

TEST(MemoryPool, ExhaustedPoolRecoversAfterReclaim) {
  CountingBackend backend;
  rt::MemoryPool pool(backend, 8 * kPage, kPage, 8 * kPage);
  Range a = pool.allocate(4 * kPage, "a");
  Range b = pool.allocate(4 * kPage, "b");
  EXPECT_NE(allocation_error(pool, kPage, "c").find("0 B left"), std::string::npos);
  pool.release(b);
  // Retired pages that are not enough: the pool waits, takes them back and still refuses.
  const std::string msg = allocation_error(pool, 6 * kPage, "d");
  EXPECT_NE(msg.find("more than the budget has left"), std::string::npos) << msg;
  EXPECT_NE(msg.find("16.0 KiB left"), std::string::npos) << msg;
  EXPECT_EQ(backend.finishes, 1);
  EXPECT_EQ(pool.used(), 4 * kPage);
  pool.release(a);
  pool.reclaim();
  EXPECT_EQ(pool.used(), 0u);
  EXPECT_EQ(pool.allocate(8 * kPage, "e").first_page, 0u);
  EXPECT_EQ(backend.arenas_created(), 1u);
}

TEST(MemoryPool, ArenaTheBackendCannotCreateIsAnErrorAndNothingChanges) {
  CountingBackend backend;
  rt::MemoryPool pool(backend, 16 * kPage, kPage, 8 * kPage);
  Range first = pool.allocate(8 * kPage, "first");
  backend.fail_arenas = true;
  try {
    pool.allocate(kPage, "second");
    FAIL() << "expected the backend's error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("fake device: cannot allocate 32.0 KiB"), std::string::npos) << e.what();
  }
  EXPECT_EQ(pool.used(), 8 * kPage);
  EXPECT_EQ(backend.arenas_created(), 1u);
  EXPECT_EQ(backend.live_arenas, 1);
  backend.fail_arenas = false;  // the backend recovers: so does the pool
  Range second = pool.allocate(kPage, "second");
  EXPECT_EQ(second.arena, 1u);
  EXPECT_FALSE(overlap(first, second));
  EXPECT_EQ(backend.arena_bytes, (std::vector<uint64_t>{8 * kPage, 8 * kPage}));
}

}  // namespace
}  // namespace mv::test
