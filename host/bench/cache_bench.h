// `megavox bench cache-update`: the page cache's update pass (host/core/cache/page_cache.h) per pass, against a
// classic CPU LRU (a linked list of slots and a page map, as the thesis compares with, notes 8.3) over the
// same kind of passes: a view of `view` consecutive pages drifting `drift` pages a pass over `pages` pages.
#pragma once
#include <cstdint>

#include "megavox/device.h"

namespace mv::bench {

struct CacheBenchConfig {
  uint32_t slots = 1024;       // 16 MiB of 16 KiB pages
  uint32_t pages = 8196;       // koala's svdag at 16K^3 in 16 KiB pages
  uint32_t page_words = 4096;
  uint32_t passes = 200;
  uint32_t view = 600;         // pages one pass needs
  uint32_t drift = 20;         // pages the view moves each pass
};

struct CacheBenchResult {
  double device_manage_ms = 0;   // mean per update: the kernels and the host's waits on them
  double device_produce_ms = 0;  // mean per update: copying the pages from host memory, uploading and placing them
  double cpu_lru_ms = 0;         // mean per update of the CPU LRU's bookkeeping alone
  double ratio = 0;              // device_manage_ms / cpu_lru_ms
  double device_hit_rate = 0;    // needed pages resident when a pass starts / needed pages
  double cpu_hit_rate = 0;
  uint64_t loads = 0, evictions = 0, bytes_uploaded = 0;  // device cache, over all passes
};

CacheBenchResult run_cache_bench(Device& dev, const CacheBenchConfig& c);

}  // namespace mv::bench
