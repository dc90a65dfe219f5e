// The explicit device-memory page cache: a fixed number of slots of one page each, a page table from page ids
// to slots, per-slot usage stamps and per-page request stamps written by whoever reads the pages (the
// traversal), and the data-parallel update pass that runs after each pass (kernels/common/page_cache.h):
// a stable LRU partition of the slots, the unique list of missing requested pages capped to the slots unused
// in the pass, eviction of the victims' old pages, one batch from the producer, and publication of the pages
// it produced: GigaVoxels' cache (Crassin, "GigaVoxels", PhD thesis, 2011, ch. 7, §7.3), as data-parallel passes.
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "common/page_cache.h"
#include "megavox/cache_stats.h"
#include "megavox/device.h"
#include "primitives/scan_plan.h"

namespace mv {

struct PageCacheConfig {
  uint32_t slots = 0;       // device slots, one page each (slots * page_words * 4 bytes of device memory)
  uint32_t pages = 0;       // page ids [0, pages)
  uint32_t page_words = 0;  // 32-bit words per page
  uint32_t max_loads = 0;   // pages loaded per update at most; 0: as many as the pass left unused slots
  // Words stored after the page table (at table()[pages] on) for the reader's own constants (a paged ssvdag's
  // level starts, read by the traversal with the table); the cache never touches them.
  std::vector<uint32_t> table_tail;
  // Words a page carries in a second plane beside its own (0: none), held in plane() slot for slot: a paged
  // DAG's subtree sizes (paging/paged_sizes.h), read by the walk that finds a hit's colour.
  uint32_t plane_words = 0;
};

// Fills `words` (page_words of them, then plane_words of the page's plane) with page `page`. Returns false, or throws, when it cannot: the page
// stays missing and the update goes on. Called for several pages at once from worker threads (a batch is
// read in parallel), so it must be thread-safe.
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

  // Loads every page, in page order into the slots in order, when there is a slot for each (slots == pages):
  // the table then maps the whole DAG as one run. A pass and an update per `batch` pages; their totals are
  // returned (a page the producer fails stays missing, to be requested like any other).
  CacheUpdateStats preload(const PageProducer& produce, uint32_t batch = 1024);

  // The most device memory an update allocates for its duration (the upload batch of up to `slots` pages and
  // their flags), which whoever sizes other buffers beside the cache leaves free.
  uint64_t update_scratch_bytes() const;

  // The distinct missing pages the current pass has asked for so far, in page order, at most `cap` of them. For
  // reading pages ahead while the pass goes on; update() then finds them again with the later ones. Where the
  // host sees the device's memory (CPU devices) it reads the stamps and the table in place once the stream is
  // idle; elsewhere (or with in_place false) the update's request kernels compact them (one wait).
  std::vector<uint32_t> missing_so_far(uint32_t cap, bool in_place = true);

  Buffer& usage() { return usage_; }        // slots words: the last stamp that used each slot
  Buffer& requests() { return requests_; }  // pages words: the last stamp that asked for each page
  // pages words: slot of each page, or MV_CACHE_NONE; then the tail; then, from runs_at(), each page's run word
  const Buffer& table() const { return table_; }
  uint32_t runs_at() const { return config_.pages + static_cast<uint32_t>(config_.table_tail.size()); }
  const Buffer& owners() const { return owner_; } // slots words: page in each slot, or MV_CACHE_NONE
  const Buffer& lru() const { return lru_; }      // slots words: every slot once, least recently used first
  // slots * page_words words, slot s at word s * page_words, then kDataSpareWords zeros (a node at a slot's last
  // word, even one whose damaged header claims eight children, and its 64-bit reads stay inside the buffer)
  const Buffer& data() const { return data_; }
  static constexpr uint32_t kDataSpareWords = 16;
  // slots * plane_words words, slot s's plane at word s * plane_words (a one-word buffer without a plane)
  const Buffer& plane() const { return plane_; }
  // After update(): its `requested` missing pages in page order, each once (those given slots first).
  const Buffer& request_list() const { return list_; }

 private:
  // Records the compaction of the pages asked for in this pass (p.n = pages) into list_, their count at
  // request_pos_[pages].
  void record_requests(const MvCacheParams& p);
  // Records the runs of the table as it will be once the stream reaches this point (runs[] in table_).
  void record_runs();
  MvCacheParams params(uint32_t n) const { return MvCacheParams{n, stamp_, 0, config_.page_words, runs_at()}; }

  Device& dev_;
  PageCacheConfig config_;
  uint32_t stamp_ = 0;
  Buffer data_, plane_, usage_, requests_, table_, owner_, lru_, lru_next_, lru_pos_, request_pos_, list_, evicted_,
      counts_, run_pos_, run_bounds_;
  ScanPlan lru_scan_, request_scan_, run_scan_;
};

}  // namespace mv
