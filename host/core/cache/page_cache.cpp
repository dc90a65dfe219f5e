#include "cache/page_cache.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <exception>
#include <string>
#include <utility>
#include <vector>

#include "megavox/error.h"
#include "megavox/primitives.h"
#include "timing.h"

namespace mv {
namespace {

using Clock = std::chrono::steady_clock;
constexpr uint32_t kLocal = 64;

}  // namespace

PageCache::PageCache(Device& dev, const PageCacheConfig& config) : dev_(dev), config_(config) {
  const PageCacheConfig& c = config_;
  if (c.slots == 0 || c.pages == 0 || c.page_words == 0)
    throw Error("page cache: slots (" + std::to_string(c.slots) + "), pages (" + std::to_string(c.pages) +
                ") and page words (" + std::to_string(c.page_words) + ") must all be at least 1");
  const uint64_t words = uint64_t{c.slots} * c.page_words;
  if (words > kMaxDeviceItems || c.pages >= kMaxDeviceItems)
    throw Error("page cache: " + std::to_string(c.slots) + " slots of " + std::to_string(c.page_words) +
                " words over " + std::to_string(c.pages) + " pages pass the " + std::to_string(kMaxDeviceItems) +
                " words one device call indexes");
  data_ = dev.alloc((words + kDataSpareWords) * 4, "page cache slots");
  const uint64_t plane_words = std::max<uint64_t>(uint64_t{c.slots} * c.plane_words, 1);
  if (plane_words > kMaxDeviceItems) throw Error("page cache: the plane passes the words one device call indexes");
  plane_ = dev.alloc(plane_words * 4, "page cache plane");
  dev.fill(plane_, 0, plane_words * 4);
  usage_ = dev.alloc(uint64_t{c.slots} * 4, "page cache usage stamps");
  owner_ = dev.alloc(uint64_t{c.slots} * 4, "page cache slot owners");
  lru_ = dev.alloc(uint64_t{c.slots} * 4, "page cache LRU list");
  lru_next_ = dev.alloc(uint64_t{c.slots} * 4, "page cache LRU list");
  lru_pos_ = dev.alloc((uint64_t{c.slots} + 1) * 4, "page cache LRU positions");
  evicted_ = dev.alloc(uint64_t{c.slots} * 4, "page cache evicted pages");
  requests_ = dev.alloc(uint64_t{c.pages} * 4, "page cache request stamps");
  table_ = dev.alloc((uint64_t{runs_at()} + c.pages) * 4, "page cache page table");
  request_pos_ = dev.alloc((uint64_t{c.pages} + 1) * 4, "page cache request positions");
  list_ = dev.alloc(uint64_t{c.pages} * 4, "page cache request list");
  counts_ = dev.alloc(8, "page cache counts");
  run_pos_ = dev.alloc((uint64_t{c.pages} + 1) * 4, "page cache run positions");
  run_bounds_ = dev.alloc(2ull * c.pages * 4, "page cache run bounds");
  lru_scan_ = plan_scan(dev, c.slots);
  request_scan_ = plan_scan(dev, c.pages);
  run_scan_ = plan_scan(dev, c.pages);
  dev.fill(data_, 0, (words + kDataSpareWords) * 4);
  dev.fill(usage_, 0, uint64_t{c.slots} * 4);  // stamp 0: never used
  dev.fill(owner_, MV_CACHE_NONE, uint64_t{c.slots} * 4);
  dev.fill(requests_, 0, uint64_t{c.pages} * 4);
  dev.fill(table_, MV_CACHE_NONE, uint64_t{c.pages} * 4);
  if (!c.table_tail.empty()) dev.upload(table_, c.table_tail.data(), c.table_tail.size() * 4, uint64_t{c.pages} * 4);
  dev.fill(table_, 0, uint64_t{c.pages} * 4, uint64_t{runs_at()} * 4);
  std::vector<uint32_t> order(c.slots);
  for (uint32_t s = 0; s < c.slots; ++s) order[s] = s;
  dev.upload(lru_, order.data(), uint64_t{c.slots} * 4);
  dev.finish();
}

uint64_t PageCache::update_scratch_bytes() const {
  const uint64_t page = dev_.page_bytes(), n = config_.max_loads ? std::min(config_.max_loads, config_.slots) : config_.slots;
  auto pages = [&](uint64_t bytes) { return (bytes + page - 1) / page * page; };
  return pages(n * config_.page_words * 4) + pages(n * config_.plane_words * 4) + pages(n * 4);
}

// The missing pages asked for in this pass, in page order, each once.
void PageCache::record_requests(const MvCacheParams& p) {
  dev_.dispatch(dev_.kernel(KernelId::cache_request_flags), dev_.groups_for(p.n, kLocal), kLocal,
                {&requests_, &table_, &request_pos_}, p);
  dev_.barrier();
  record_scan(dev_, request_scan_, request_pos_, request_pos_);
  dev_.dispatch(dev_.kernel(KernelId::cache_request_compact), dev_.groups_for(p.n, kLocal), kLocal,
                {&request_pos_, &list_}, p);
}

void PageCache::record_runs() {
  const MvCacheParams p = params(config_.pages);
  const uint32_t groups = dev_.groups_for(p.n, kLocal);
  dev_.dispatch(dev_.kernel(KernelId::cache_run_flags), groups, kLocal, {&table_, &run_pos_}, p);
  dev_.barrier();
  record_scan(dev_, run_scan_, run_pos_, run_pos_);
  dev_.dispatch(dev_.kernel(KernelId::cache_run_bounds), groups, kLocal, {&table_, &run_pos_, &run_bounds_}, p);
  dev_.barrier();
  dev_.dispatch(dev_.kernel(KernelId::cache_run_expand), groups, kLocal, {&table_, &run_pos_, &run_bounds_}, p);
}

CacheUpdateStats PageCache::preload(const PageProducer& produce, uint32_t batch) {
  const PageCacheConfig& c = config_;
  CacheUpdateStats total;
  if (c.slots < c.pages) return total;
  batch = std::max<uint32_t>(batch, 1);
  std::vector<uint32_t> asked(batch);
  for (uint32_t first = 0; first < c.pages; first += batch) {
    const uint32_t n = std::min(batch, c.pages - first);
    const uint32_t t = begin_pass();
    std::fill_n(asked.begin(), n, t);
    dev_.upload(requests_, asked.data(), uint64_t{n} * 4, uint64_t{first} * 4);
    const CacheUpdateStats st = update(produce);
    total.requested += st.requested, total.loaded += st.loaded, total.failed += st.failed;
    total.evicted += st.evicted, total.bytes_uploaded += st.bytes_uploaded;
    total.manage_seconds += st.manage_seconds, total.produce_seconds += st.produce_seconds;
    if (total.first_error.empty()) total.first_error = st.first_error;
  }
  total.stamp = stamp_;
  return total;
}

std::vector<uint32_t> PageCache::missing_so_far(uint32_t cap, bool in_place) {
  if (stamp_ == 0) throw Error("page cache: no pass has begun (begin_pass)");
  const PageCacheConfig& c = config_;
  const auto* asked = static_cast<const uint32_t*>(dev_.host_view(requests_));
  const auto* table = static_cast<const uint32_t*>(dev_.host_view(table_));
  if (in_place && asked && table) {  // a CPU device: the stamps and the table are read in place, with no kernels to wait for
    dev_.finish();
    std::vector<uint32_t> pages;
    for (uint32_t page = 0; page < c.pages && pages.size() < cap; ++page)
      if (asked[page] == stamp_ && table[page] == MV_CACHE_NONE) pages.push_back(page);
    return pages;
  }
  record_requests(params(c.pages));
  dev_.copy(request_pos_, counts_, 4, uint64_t{c.pages} * 4, 4);
  dev_.barrier();
  uint32_t count = 0;
  dev_.download(counts_, &count, 4, 4);
  std::vector<uint32_t> pages(std::min(count, cap));
  if (!pages.empty()) dev_.download(list_, pages.data(), pages.size() * 4);
  return pages;
}

uint32_t PageCache::begin_pass() {
  if (stamp_ == 0xffffffffu) throw Error("page cache: 2^32 - 1 passes made; the stamps would wrap");
  return ++stamp_;
}

CacheUpdateStats PageCache::update(const PageProducer& produce) {
  if (stamp_ == 0) throw Error("page cache: update before the first pass (begin_pass)");
  const auto t0 = Clock::now();
  const PageCacheConfig& c = config_;
  CacheUpdateStats st;
  st.stamp = stamp_;

  // LRU: slots unused in this pass first, then the used ones, each side in its previous order
  MvCacheParams p = params(c.slots);
  dev_.dispatch(dev_.kernel(KernelId::cache_lru_flags), dev_.groups_for(c.slots, kLocal), kLocal,
                {&usage_, &lru_, &lru_pos_}, p);
  dev_.barrier();
  record_scan(dev_, lru_scan_, lru_pos_, lru_pos_);
  dev_.dispatch(dev_.kernel(KernelId::cache_lru_scatter), dev_.groups_for(c.slots, kLocal), kLocal,
                {&lru_, &lru_pos_, &lru_next_}, p);
  p.n = c.pages;
  record_requests(p);
  std::swap(lru_, lru_next_);
  dev_.copy(lru_pos_, counts_, 4, uint64_t{c.slots} * 4, 0);
  dev_.copy(request_pos_, counts_, 4, uint64_t{c.pages} * 4, 4);
  dev_.barrier();
  uint32_t counts[2] = {0, 0};
  dev_.download(counts_, counts, 8);
  const uint32_t unused = counts[0];
  st.used_slots = c.slots - unused;
  st.requested = counts[1];
  st.over_capacity = st.requested > unused;
  uint32_t n = std::min(st.requested, unused);
  if (c.max_loads != 0) n = std::min(n, c.max_loads);
  st.dropped = st.requested - n;
  if (n == 0) {
    st.manage_seconds = seconds_since(t0);
    return st;
  }

  // the victims: the n least recently used slots, all unused in this pass; their old pages leave the table
  p.n = n;
  p.count = n;
  dev_.dispatch(dev_.kernel(KernelId::cache_evict), dev_.groups_for(n, kLocal), kLocal,
                {&lru_, &table_, &owner_, &evicted_}, p);
  dev_.barrier();
  std::vector<uint32_t> pages(n), evicted(n);
  dev_.download(list_, pages.data(), uint64_t{n} * 4);
  dev_.download(evicted_, evicted.data(), uint64_t{n} * 4);
  for (uint32_t old : evicted) st.evicted += old != MV_CACHE_NONE ? 1u : 0u;

  // one batch from the producer: the pages read in parallel off the calling thread (TBB workers), then one
  // asynchronous upload of the batch and its flags, placed into the victims' slots
  const auto tp = Clock::now();
  // (a page's plane words follow its own in the producer's span, and are staged after the whole batch's pages)
  const uint64_t batch_words = uint64_t{n} * c.page_words, plane_batch = uint64_t{n} * c.plane_words;
  std::vector<uint32_t> staging(batch_words + plane_batch, 0), ok(n, 0);
  std::vector<std::string> errors(n);
  tbb::parallel_for(uint32_t{0}, n, [&](uint32_t i) {
    std::vector<uint32_t> own(c.plane_words ? c.page_words + c.plane_words : 0);
    std::span<uint32_t> words = c.plane_words ? std::span<uint32_t>(own)
                                              : std::span<uint32_t>(staging.data() + uint64_t{i} * c.page_words, c.page_words);
    try {
      ok[i] = produce(pages[i], words) ? 1u : 0u;
    } catch (const std::exception& e) {
      errors[i] = "page " + std::to_string(pages[i]) + ": " + e.what();
    }
    if (c.plane_words) {
      std::copy_n(own.begin(), c.page_words, staging.begin() + static_cast<std::ptrdiff_t>(uint64_t{i} * c.page_words));
      std::copy_n(own.begin() + c.page_words, c.plane_words,
                  staging.begin() + static_cast<std::ptrdiff_t>(batch_words + uint64_t{i} * c.plane_words));
    }
  });
  for (uint32_t i = 0; i < n; ++i) {
    st.loaded += ok[i];
    if (st.first_error.empty() && !errors[i].empty()) st.first_error = errors[i];  // the lowest page's
  }
  st.failed = n - st.loaded;
  Buffer staged = dev_.alloc(batch_words * 4, "page cache upload batch");
  Buffer ok_buf = dev_.alloc(uint64_t{n} * 4, "page cache produced flags");
  Buffer plane_staged = plane_batch ? dev_.alloc(plane_batch * 4, "page cache plane batch") : Buffer();
  dev_.upload_async(staged, staging.data(), batch_words * 4);
  if (plane_batch) dev_.upload_async(plane_staged, staging.data() + batch_words, plane_batch * 4);
  dev_.upload_async(ok_buf, ok.data(), uint64_t{n} * 4);
  dev_.barrier();
  st.bytes_uploaded = (batch_words + plane_batch) * 4;
  p.n = static_cast<uint32_t>(batch_words);  // at most slots * page_words, checked at construction
  dev_.dispatch(dev_.kernel(KernelId::cache_place), dev_.groups_for(batch_words, kLocal), kLocal,
                {&lru_, &ok_buf, &staged, &data_}, p);
  if (plane_batch) {  // the plane: the same placement with its own stride, from the batch's second part
    MvCacheParams q = p;
    q.n = static_cast<uint32_t>(plane_batch);
    q.page_words = c.plane_words;
    dev_.dispatch(dev_.kernel(KernelId::cache_place), dev_.groups_for(plane_batch, kLocal), kLocal,
                  {&lru_, &ok_buf, &plane_staged, &plane_}, q);
  }
  dev_.finish();  // placing the batch is uploading, timed apart from management
  st.produce_seconds = seconds_since(tp);

  p.n = n;
  dev_.dispatch(dev_.kernel(KernelId::cache_publish), dev_.groups_for(n, kLocal), kLocal,
                {&lru_, &list_, &ok_buf, &table_, &owner_, &usage_}, p);
  dev_.barrier();
  record_runs();
  dev_.finish();
  st.manage_seconds = seconds_since(t0) - st.produce_seconds;
  return st;
}

}  // namespace mv
