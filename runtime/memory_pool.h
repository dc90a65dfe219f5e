// Device memory budget and page pool.
//
// Device memory is a budget, not a hope: the pool owns a few large allocations ("arenas", created on
// demand, each at most min(largest allocation the device allows, what is left of the budget)) and
// hands out runs of fixed-size pages from them, first fit. An array may span many pages (but one arena).
// A request that cannot be placed throws mv::Error naming what was asked, what is left and the budget —
// never a failure deep inside a driver. The page cache of later stages builds on these pages.
//
// Released ranges are only retired: recorded work may still use them, so they return to the free pages
// at the next reclaim() (Device::finish), or when an allocation would otherwise fail (after a finish).
#pragma once
#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "backend.h"

namespace mv::rt {

class MemoryPool {
 public:
  struct Range {
    uint32_t arena = 0;
    uint64_t first_page = 0;
    uint64_t pages = 0;
  };

  MemoryPool(Backend& backend, uint64_t budget_bytes, uint64_t page_bytes, uint64_t max_arena_bytes);

  Range allocate(uint64_t bytes, std::string_view what);
  void release(const Range& range);  // retire: free again after the next reclaim()
  void reclaim();                     // call only when the device is idle
  // Frees the storage of every arena that holds no pages (call only when the device is idle, after reclaim);
  // a later allocation creates a new arena. Returns the bytes freed.
  uint64_t trim();

  BackendArena& arena(uint32_t index) { return *arenas_[index].memory; }
  uint64_t budget() const { return budget_; }
  uint64_t used() const { return used_pages_ * page_bytes_; }
  // The most used() has been since the last reset_peak() (or since the pool was made).
  uint64_t peak() const { return peak_pages_ * page_bytes_; }
  void reset_peak() { peak_pages_ = used_pages_; }
  uint64_t page_bytes() const { return page_bytes_; }
  uint64_t max_arena_bytes() const { return max_arena_bytes_; }

 private:
  struct Arena {
    std::unique_ptr<BackendArena> memory;
    std::vector<bool> used;  // one flag per page
    uint64_t touched = 0;    // host-visible storage: bytes from the start already touched (handed out once)
  };
  // Touches the part of a freshly placed range that no earlier range reached (host-visible arenas only).
  Range touch(const Range& range);
  bool find_run(const Arena& arena, uint64_t pages, uint64_t& first) const;
  bool place(uint64_t pages, Range& out);
  uint64_t largest_free_run() const;

  Backend& backend_;
  uint64_t budget_;
  uint64_t page_bytes_;
  uint64_t max_arena_bytes_;
  uint64_t arena_bytes_total_ = 0;
  uint64_t used_pages_ = 0;
  uint64_t peak_pages_ = 0;
  std::vector<Arena> arenas_;
  std::vector<Range> retired_;
};

}  // namespace mv::rt
