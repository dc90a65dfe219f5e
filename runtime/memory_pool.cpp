#include "memory_pool.h"

#include <algorithm>

#include "huge_pages.h"
#include "megavox/device.h"
#include "megavox/error.h"

namespace mv::rt {

MemoryPool::MemoryPool(Backend& backend, uint64_t budget_bytes, uint64_t page_bytes, uint64_t max_arena_bytes)
    : backend_(backend),
      budget_(budget_bytes / page_bytes * page_bytes),
      page_bytes_(page_bytes),
      max_arena_bytes_(std::min(max_arena_bytes, budget_bytes) / page_bytes * page_bytes) {
  if (budget_ < page_bytes_)
    throw Error("device memory budget " + format_bytes(budget_bytes) + " is smaller than one page (" +
                format_bytes(page_bytes) + ")");
}

bool MemoryPool::find_run(const Arena& arena, uint64_t pages, uint64_t& first) const {
  uint64_t run = 0;
  for (uint64_t p = 0; p < arena.used.size(); ++p) {
    run = arena.used[p] ? 0 : run + 1;
    if (run == pages) {
      first = p + 1 - pages;
      return true;
    }
  }
  return false;
}

uint64_t MemoryPool::largest_free_run() const {
  uint64_t best = 0;
  for (const Arena& a : arenas_) {
    uint64_t run = 0;
    for (bool u : a.used) best = std::max(best, run = u ? 0 : run + 1);
  }
  // A new arena could still be created from the part of the budget not yet allocated.
  uint64_t fresh = std::min(max_arena_bytes_, budget_ - arena_bytes_total_) / page_bytes_;
  return std::max(best, fresh) * page_bytes_;
}

MemoryPool::Range MemoryPool::allocate(uint64_t bytes, std::string_view what) {
  uint64_t pages = std::max<uint64_t>(1, (bytes + page_bytes_ - 1) / page_bytes_);
  uint64_t need = pages * page_bytes_;
  auto fail = [&](const std::string& why) -> DeviceMemoryError {
    return DeviceMemoryError("device memory: " + std::string(what) + " needs " + format_bytes(bytes) + ", " + why +
                 " (budget " + format_bytes(budget_) + ", " + format_bytes(budget_ - used()) +
                 " left, largest free run " + format_bytes(largest_free_run()) +
                 "); raise the device memory budget or use a smaller problem");
  };
  if (need > budget_) throw fail("more than the whole budget");
  if (need > max_arena_bytes_)
    throw fail("more than one allocation may hold on " + backend_.info().name + " (" +
               format_bytes(max_arena_bytes_) + ")");
  Range range;
  if (place(pages, range)) return touch(range);
  if (!retired_.empty()) {
    backend_.finish();  // the retired pages are needed: wait until no recorded work can touch them
    reclaim();
    if (place(pages, range)) return touch(range);
  }
  if (need > budget_ - used()) throw fail("more than the budget has left");
  throw fail("no free run of pages is large enough");
}

// First fit in the existing arenas, else a new arena from the budget not yet allocated.
bool MemoryPool::place(uint64_t pages, Range& out) {
  uint64_t need = pages * page_bytes_;
  if (need > budget_ - used()) return false;
  uint64_t first = 0;
  for (uint32_t i = 0; i < arenas_.size(); ++i) {
    if (find_run(arenas_[i], pages, first)) {
      std::fill_n(arenas_[i].used.begin() + static_cast<std::ptrdiff_t>(first), pages, true);
      used_pages_ += pages;
      peak_pages_ = std::max(peak_pages_, used_pages_);
      out = {i, first, pages};
      return true;
    }
  }
  uint64_t arena_bytes = std::min(max_arena_bytes_, budget_ - arena_bytes_total_) / page_bytes_ * page_bytes_;
  if (arena_bytes < need) return false;
  Arena arena;
  arena.memory = backend_.create_arena(arena_bytes);
  arena.used.assign(arena_bytes / page_bytes_, false);
  std::fill_n(arena.used.begin(), pages, true);
  arenas_.push_back(std::move(arena));
  arena_bytes_total_ += arena_bytes;
  used_pages_ += pages;
  peak_pages_ = std::max(peak_pages_, used_pages_);
  out = {static_cast<uint32_t>(arenas_.size() - 1), 0, pages};
  return true;
}

MemoryPool::Range MemoryPool::touch(const Range& range) {
  Arena& a = arenas_[range.arena];
  const uint64_t end = (range.first_page + range.pages) * page_bytes_;
  if (a.memory->host && end > a.touched) {
    // Fresh host memory faults on its first touch; whoever fills the range next (an upload's single memcpy,
    // a kernel) would take those faults alone. Storage below `touched` holds data or did: never written here.
    prefault(static_cast<char*>(a.memory->host) + a.touched, end - a.touched);
    a.touched = end;
  }
  return range;
}

uint64_t MemoryPool::trim() {
  uint64_t freed = 0;
  for (Arena& a : arenas_) {
    if (!a.memory || std::find(a.used.begin(), a.used.end(), true) != a.used.end()) continue;
    const uint64_t bytes = a.used.size() * page_bytes_;
    a.memory.reset();
    a.used.clear();  // no run fits an arena without pages: place() passes over it
    arena_bytes_total_ -= bytes;
    freed += bytes;
  }
  return freed;
}

void MemoryPool::release(const Range& range) { retired_.push_back(range); }

void MemoryPool::reclaim() {
  for (const Range& r : retired_) {
    auto& used = arenas_.at(r.arena).used;
    std::fill_n(used.begin() + static_cast<std::ptrdiff_t>(r.first_page), r.pages, false);
    used_pages_ -= r.pages;
  }
  retired_.clear();
}

}  // namespace mv::rt
