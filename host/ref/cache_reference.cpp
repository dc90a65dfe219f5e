#include "cache_reference.h"

#include <algorithm>

namespace mv::ref {

CacheState cache_init(uint32_t slots, uint32_t pages, uint32_t page_words) {
  CacheState s;
  s.page_words = page_words;
  s.usage.assign(slots, 0);
  s.requests.assign(pages, 0);
  s.table.assign(pages, kCacheNone);
  s.owner.assign(slots, kCacheNone);
  for (uint32_t i = 0; i < slots; ++i) s.lru.push_back(i);
  s.data.assign(uint64_t{slots} * page_words, 0);
  s.runs.assign(pages, 0);
  return s;
}

CacheStep cache_update(CacheState& s, uint32_t stamp, uint32_t max_loads,
                       const std::function<bool(uint32_t, std::span<uint32_t>)>& produce) {
  CacheStep step;
  // least recently used first: the slots this pass did not use keep their order ahead of the ones it did
  std::stable_partition(s.lru.begin(), s.lru.end(), [&](uint32_t slot) { return s.usage[slot] != stamp; });
  for (uint32_t slot : s.lru) step.unused += s.usage[slot] != stamp ? 1u : 0u;
  std::vector<uint32_t> wanted;
  for (uint32_t pg = 0; pg < s.requests.size(); ++pg)
    if (s.requests[pg] == stamp && s.table[pg] == kCacheNone) wanted.push_back(pg);
  step.requested = static_cast<uint32_t>(wanted.size());
  uint32_t n = std::min(step.requested, step.unused);
  if (max_loads != 0) n = std::min(n, max_loads);
  step.dropped = step.requested - n;
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t slot = s.lru[i], pg = wanted[i];
    step.pages.push_back(pg);
    step.victims.push_back(slot);
    if (s.owner[slot] != kCacheNone) {
      s.table[s.owner[slot]] = kCacheNone;
      ++step.evicted;
    }
    s.owner[slot] = kCacheNone;
    std::vector<uint32_t> words(s.page_words, 0);
    bool ok = false;
    try {
      ok = produce(pg, words);
    } catch (...) {
      ok = false;
    }
    if (!ok) {
      ++step.failed;
      continue;
    }
    std::copy(words.begin(), words.end(), s.data.begin() + uint64_t{slot} * s.page_words);
    s.table[pg] = slot;
    s.owner[slot] = pg;
    s.usage[slot] = stamp + 1;  // counts as used by the next pass, which asked for it
    ++step.loaded;
  }
  // runs: walk the pages once, extending the current run while the next page sits in the next slot
  const uint32_t pages = static_cast<uint32_t>(s.table.size());
  for (uint32_t first = 0; first < pages;) {
    if (s.table[first] == kCacheNone) {
      ++first;
      continue;
    }
    uint32_t end = first + 1;
    while (end < pages && s.table[end] != kCacheNone && s.table[end] == s.table[end - 1] + 1) ++end;
    for (uint32_t pg = first; pg < end; ++pg)
      s.runs[pg] = (std::min(pg - first, 0xffffu) << 16) | std::min(end - pg, 0xffffu);
    first = end;
  }
  return step;
}

}  // namespace mv::ref
