// The explicit device-memory page cache: a fixed number of slots of one page each, a page table from page ids
// to slots, per-slot usage stamps and per-page request stamps written by whoever reads the pages (the
// traversal), and the data-parallel update pass that runs after each pass (kernels/common/page_cache.h):
// a stable LRU partition of the slots, the unique list of missing requested pages capped to the slots unused
// in the pass, eviction of the victims' old pages, one batch from the producer, and publication of the pages
// it produced. Notes: ../shared/notes/gigavoxels-cache.md, sections 5-6.
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <string>

#include "megavox/device.h"
#include "scan_plan.h"

namespace mv {

struct PageCacheConfig {
  uint32_t slots = 0;       // device slots, one page each (slots * page_words * 4 bytes of device memory)
  uint32_t pages = 0;       // page ids [0, pages)
  uint32_t page_words = 0;  // 32-bit words per page
  uint32_t max_loads = 0;   // pages loaded per update at most; 0: as many as the pass left unused slots
};

// What one update did. requested counts the distinct missing pages asked for in the pass; of those, the first
// `loaded + failed` (in page order) got a victim slot, and `dropped` did not (over the unused slots or
// max_loads: asked again by the next pass that still needs them).
struct CacheUpdateStats {
  uint32_t stamp = 0;          // the pass this update followed
  uint32_t used_slots = 0;     // slots whose usage stamp is this pass (read in it, or loaded for it)
  uint32_t requested = 0;
  uint32_t loaded = 0;         // produced and entered into the page table
  uint32_t failed = 0;         // the producer could not make them: still missing, their slots free
  uint32_t evicted = 0;        // resident pages whose slots were reused
  uint32_t dropped = 0;
  bool over_capacity = false;  // more requests than slots unused in the pass (the frame's working set does
                               // not fit: the used pages stay, the rest waits)
  uint64_t bytes_uploaded = 0;
  double manage_seconds = 0;   // the kernels and the host's waits on them
  double produce_seconds = 0;  // the producer, the upload of its batch and its placement into the slots
  std::string first_error;     // the first producer failure's message, if it threw one
};

// Fills `words` (page_words of them) with page `page`. Returns false, or throws, when it cannot: the page
// stays missing and the update goes on.
using PageProducer = std::function<bool(uint32_t page, std::span<uint32_t> words)>;

class PageCache {
 public:
  // Throws mv::Error on an empty or oversized configuration, DeviceMemoryError when the slots or the
  // bookkeeping do not fit the device budget.
  PageCache(Device& dev, const PageCacheConfig& config);

  const PageCacheConfig& config() const { return config_; }

  // Starts the next pass and returns its stamp (1, 2, ...): what the pass writes into usage() for every slot
  // it reads and into requests() for every page it misses.
  uint32_t begin_pass();
  uint32_t stamp() const { return stamp_; }

  // The update pass after the current pass. Waits for the device four times when pages load (the counts, the
  // victims, the placed batch, the end) and once when none do.
  CacheUpdateStats update(const PageProducer& produce);

  Buffer& usage() { return usage_; }        // slots words: the last stamp that used each slot
  Buffer& requests() { return requests_; }  // pages words: the last stamp that asked for each page
  const Buffer& table() const { return table_; }  // pages words: slot of each page, or MV_CACHE_NONE
  const Buffer& owners() const { return owner_; } // slots words: page in each slot, or MV_CACHE_NONE
  const Buffer& lru() const { return lru_; }      // slots words: every slot once, least recently used first
  const Buffer& data() const { return data_; }    // slots * page_words words: slot s at word s * page_words
  // After update(): its `requested` missing pages in page order, each once (those given slots first).
  const Buffer& request_list() const { return list_; }

 private:
  Device& dev_;
  PageCacheConfig config_;
  uint32_t stamp_ = 0;
  Buffer data_, usage_, requests_, table_, owner_, lru_, lru_next_, lru_pos_, request_pos_, list_, evicted_,
      counts_;
  ScanPlan lru_scan_, request_scan_;
};

}  // namespace mv
