// Plain C++ reference of the page cache's update pass (host/core/cache/page_cache.h), written from the notes'
// description (gigavoxels-cache.md 6.2-6.9) with sequential loops and std::stable_partition, sharing no
// code with the kernels: the oracle the device cache is compared with, state for state.
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

namespace mv::ref {

inline constexpr uint32_t kCacheNone = 0xffffffffu;

struct CacheState {
  uint32_t page_words = 0;
  std::vector<uint32_t> usage;     // per slot: last stamp that used it
  std::vector<uint32_t> requests;  // per page: last stamp that asked for it
  std::vector<uint32_t> table;     // per page: its slot or kCacheNone
  std::vector<uint32_t> owner;     // per slot: its page or kCacheNone
  std::vector<uint32_t> lru;       // slots, least recently used first
  std::vector<uint32_t> data;      // slots * page_words
  // per resident page: its run (the most consecutive resident pages around it in consecutive slots) as the
  // pages before it and from it on, each capped at 0xffff, in the high and low halves; a missing page's word
  // is left as it was
  std::vector<uint32_t> runs;
};

struct CacheStep {
  uint32_t requested = 0, loaded = 0, failed = 0, evicted = 0, dropped = 0, unused = 0;
  std::vector<uint32_t> pages;    // the pages given a slot, in order
  std::vector<uint32_t> victims;  // their slots
};

CacheState cache_init(uint32_t slots, uint32_t pages, uint32_t page_words);

// The update after pass `stamp`; `produce` fills a page (false: it stays missing).
CacheStep cache_update(CacheState& s, uint32_t stamp, uint32_t max_loads,
                       const std::function<bool(uint32_t, std::span<uint32_t>)>& produce);

}  // namespace mv::ref
