#include "cache_bench.h"

#include <algorithm>
#include <cstring>
#include <list>
#include <vector>

#include "common/page_cache.h"
#include "stopwatch.h"
#include "cache/page_cache.h"
#include "megavox/error.h"

namespace mv::bench {
namespace {

// The baseline: LRU as a CPU would keep it, a list of slots (least recent first) moved on every use.
class CpuLru {
 public:
  CpuLru(uint32_t slots, uint32_t pages) : table_(pages, MV_CACHE_NONE), owner_(slots, MV_CACHE_NONE),
                                            asked_(pages, 0), used_(slots, 0) {
    for (uint32_t s = 0; s < slots; ++s) where_.push_back(order_.insert(order_.end(), s));
  }
  uint32_t slot_of(uint32_t page) const { return table_[page]; }
  // used: slots read in pass t; asked: pages missed in it (repeats allowed). Returns the pages loaded.
  uint32_t update(uint32_t t, const std::vector<uint32_t>& used, const std::vector<uint32_t>& asked) {
    for (uint32_t s : used) {
      used_[s] = t;
      order_.splice(order_.end(), order_, where_[s]);
    }
    uint32_t loaded = 0;
    for (uint32_t pg : asked) {
      if (asked_[pg] == t || table_[pg] != MV_CACHE_NONE) continue;
      asked_[pg] = t;
      const uint32_t s = order_.front();
      if (used_[s] >= t) break;  // only slots used in (or loaded for) this pass are left
      if (owner_[s] != MV_CACHE_NONE) table_[owner_[s]] = MV_CACHE_NONE;
      owner_[s] = pg;
      table_[pg] = s;
      used_[s] = t + 1;
      order_.splice(order_.end(), order_, where_[s]);
      ++loaded;
    }
    return loaded;
  }

 private:
  std::list<uint32_t> order_;
  std::vector<std::list<uint32_t>::iterator> where_;
  std::vector<uint32_t> table_, owner_, asked_, used_;
};

}  // namespace

CacheBenchResult run_cache_bench(Device& dev, const CacheBenchConfig& c) {
  if (c.passes == 0 || c.view == 0 || c.view > c.pages) throw Error("bench cache-update: need passes >= 1 and 1 <= view <= pages");
  PageCache cache(dev, {c.slots, c.pages, c.page_words, 0, {}});
  CpuLru cpu(c.slots, c.pages);
  // the "file": every page's words in host memory, so producing a page is one copy
  std::vector<uint32_t> source(uint64_t{c.pages} * c.page_words);
  for (uint64_t i = 0; i < source.size(); ++i) source[i] = static_cast<uint32_t>(i * 2654435761u);
  auto produce = [&](uint32_t pg, std::span<uint32_t> w) {
    std::memcpy(w.data(), source.data() + uint64_t{pg} * c.page_words, w.size() * 4);
    return true;
  };
  std::vector<uint32_t> usage(c.slots, 0), requests(c.pages, 0), table(c.pages);
  CacheBenchResult r;
  uint64_t needed = 0, dev_hits = 0, cpu_hits = 0;
  double manage = 0, produce_s = 0, cpu_s = 0;
  for (uint32_t pass = 0; pass < c.passes; ++pass) {
    const uint32_t first = static_cast<uint32_t>(uint64_t{pass} * c.drift % c.pages);
    // what the traversal would write (not timed): the view's resident slots and missing pages
    dev.download(cache.table(), table.data(), uint64_t{c.pages} * 4);
    const uint32_t t = cache.begin_pass();
    std::vector<uint32_t> cpu_used, cpu_asked;
    for (uint32_t k = 0; k < c.view; ++k) {
      const uint32_t pg = (first + k) % c.pages;
      ++needed;
      if (table[pg] != MV_CACHE_NONE) {
        usage[table[pg]] = t;
        ++dev_hits;
      } else {
        requests[pg] = t;
      }
      if (cpu.slot_of(pg) != MV_CACHE_NONE) {
        cpu_used.push_back(cpu.slot_of(pg));
        ++cpu_hits;
      } else {
        cpu_asked.push_back(pg);
      }
    }
    dev.upload(cache.usage(), usage.data(), uint64_t{c.slots} * 4);
    dev.upload(cache.requests(), requests.data(), uint64_t{c.pages} * 4);
    const CacheUpdateStats st = cache.update(produce);
    // a page loaded for this pass counts as used by the next one, as in the device cache
    dev.download(cache.usage(), usage.data(), uint64_t{c.slots} * 4);
    manage += st.manage_seconds;
    produce_s += st.produce_seconds;
    r.loads += st.loaded;
    r.evictions += st.evicted;
    r.bytes_uploaded += st.bytes_uploaded;
    const auto t0 = Clock::now();
    cpu.update(t, cpu_used, cpu_asked);
    cpu_s += since(t0);
  }
  r.device_manage_ms = 1e3 * manage / c.passes;
  r.device_produce_ms = 1e3 * produce_s / c.passes;
  r.cpu_lru_ms = 1e3 * cpu_s / c.passes;
  r.ratio = r.cpu_lru_ms > 0 ? r.device_manage_ms / r.cpu_lru_ms : 0;
  r.device_hit_rate = double(dev_hits) / double(needed);
  r.cpu_hit_rate = double(cpu_hits) / double(needed);
  return r;
}

}  // namespace mv::bench
