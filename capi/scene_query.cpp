// A C API scene's file and tracer: a paged .mvx kept paged (mapped, pages read on demand), traced resident
// when its nodes fit what is left of the device budget, else through a page cache sized from that budget; exact
// ray queries over the cache (a batch repeats, split smaller where the cache cannot hold its pages, until no ray
// stopped at a missing page), and what the queries streamed and held.
#include <algorithm>
#include <cstdio>

#include "cache/page_cache.h"
#include "common/trace_types.h"
#include "handles.h"

namespace {

// A ray's buffers on the device during a query: the ray, its hit record and its colour word.
constexpr uint64_t kRayDeviceBytes = 4 * (MV_RAY_FLOATS + MV_HIT_WORDS + 1);
// Pages a cache holds at least (smaller budgets are refused before the query). A ray that reads more pages
// than the cache holds, alone in its batch, fails its query with a message naming cache_memory=.
constexpr uint64_t kMinCachePages = 64;
// What a query keeps free beside the scene for its ray batches (a quarter of what is left, at most this).
constexpr uint64_t kRayRoomBytes = uint64_t{64} << 20;
// The cache's bookkeeping beside its slots (a dozen small buffers and the update's scans), in device pool pages.
constexpr uint64_t kCacheBookkeepingPages = 32;

// What the device budget has left.
uint64_t budget_left(const mv::Device& dev) {
  return dev.memory_budget() - std::min(dev.memory_budget(), dev.memory_used());
}

}  // namespace

void MvSceneTy::open() {
  std::lock_guard<std::mutex> g(open_lock_);
  if (opened_) return;
  if (mv::is_paged_mvx(path)) paged_ = std::make_shared<const mv::PagedDag>(mv::open_paged_mvx(path));
  else file_ = std::make_unique<mv::MvxFile>(mv::read_mvx(path));
  opened_ = true;
}

MvSceneTy::Facts MvSceneTy::facts() {
  open();
  Facts f;
  if (paged_) {
    f.encoding = paged_->encoding;
    f.grid = paged_->grid;
    f.bounds = paged_->bounds;
    f.levels = paged_->levels;
    f.voxels = paged_->voxels;
    f.bytes = paged_->words * 4;
    f.colour_entries = paged_->colour_entries;
  } else {
    f.encoding = file_->dag.encoding;
    f.grid = file_->grid;
    f.bounds = file_->bounds;
    f.levels = file_->dag.levels;
    f.voxels = file_->voxels;
    f.bytes = file_->dag.bytes();
    f.colour_entries = file_->colours.size() / 3;
  }
  return f;
}

const mv::MvxFile& MvSceneTy::file() {
  open();
  std::lock_guard<std::mutex> g(open_lock_);
  if (!file_) file_ = std::make_unique<mv::MvxFile>(mv::read_mvx(path));
  return *file_;
}

mv::Tracer& MvSceneTy::tracer_locked() {
  if (tracer_) return *tracer_;
  open();
  mv::Device& dev = *device->device;
  if (!paged_) {
    tracer_ = std::make_unique<mv::Tracer>(dev, *file_);
    return *tracer_;
  }
  // a cache slot: a page, and its size plane where the file's colours stream with it
  const uint64_t page_bytes = uint64_t{paged_->page_words + (paged_->colour ? paged_->plane_words : 0)} * 4;
  const uint64_t stream = uint64_t{paged_->pages} * page_bytes;
  dev.finish();  // what released scenes held is free again once the device is idle
  const uint64_t free = budget_left(dev);
  const uint64_t ray_room = std::min(free / 4, kRayRoomBytes);
  if (!device->cache_memory && stream + ray_room <= free) {
    // it fits: one preloaded run of pages (with their size plane: colours through the pages), or resident with
    // its colours from the whole file where it has no plane (written before .mvx version 5)
    if (paged_->has_colours && !paged_->colour) tracer_ = std::make_unique<mv::Tracer>(dev, file());
    else tracer_ = std::make_unique<mv::Tracer>(dev, mv::PagedDag(*paged_), stream);
  } else {
    // the update's upload batch can take as much again as the slots it fills: half of what is left each
    const uint64_t fixed = kCacheBookkeepingPages * dev.page_bytes() + ray_room;
    uint64_t cache = device->cache_memory ? device->cache_memory : free > fixed ? (free - fixed) / 2 : 0;
    cache = std::min(cache / page_bytes * page_bytes, stream);
    if (cache < std::min(stream, kMinCachePages * page_bytes))
      throw mv::capi::ApiError(
          MV_ERROR_OUT_OF_MEMORY,
          path + ": a page cache of " + std::to_string(cache >> 10) + " KiB is left of the device budget, below " +
              std::to_string(kMinCachePages) + " pages of " + std::to_string(page_bytes >> 10) +
              " KiB (raise memory= or cache_memory=, or release other scenes)");
    tracer_ = std::make_unique<mv::Tracer>(dev, mv::PagedDag(*paged_), cache);
  }
  pages_streamed_ += tracer_->preloaded().loaded;
  return *tracer_;
}

namespace {

// A paged tracer's passes since its last trace: counted, and a page that could not be read fails the query
// (else its rays would wait for it forever).
void account_passes(const mv::Tracer& t, const std::string& path, uint64_t& passes, uint64_t& pages) {
  for (const mv::CacheUpdateStats& st : t.last_passes()) {
    ++passes;
    pages += st.loaded;
    if (st.failed)
      throw mv::IoError(st.first_error.empty() ? path + ": a page could not be read" : st.first_error);
  }
}

}  // namespace

std::vector<mv::RayHit> MvSceneTy::trace_locked(const std::vector<mv::Ray>& rays, const mv::TraceOptions& options,
                                                std::vector<uint32_t>* colours) {
  mv::Tracer& t = tracer_locked();
  std::vector<mv::RayHit> out = t.trace(rays, options, colours);
  if (!t.paged()) {
    ++passes_;
    return out;
  }
  account_passes(t, path, passes_, pages_streamed_);
  // Rays that stopped at a missing page (the batch's pages did not fit the cache together) go again, in
  // batches half the size each round, down to single rays; in the Morton order of where they stopped, so a
  // batch's rays continue through neighbouring nodes and share their pages.
  std::vector<size_t> waiting;
  for (size_t i = 0; i < out.size(); ++i)
    if (out[i].hit && out[i].coarse) waiting.push_back(i);
  size_t batch = waiting.size();
  std::vector<mv::Ray> sub;
  std::vector<uint32_t> sub_colours;
  std::vector<uint32_t>* want_colours = colours && !colours->empty() ? &sub_colours : nullptr;
  std::vector<uint64_t> key(out.size());
  while (!waiting.empty()) {
    for (size_t i : waiting) {
      const mv::RayHit& h = out[i];
      uint64_t k = 0;
      for (uint32_t b = 0; b < 21; ++b)
        for (int a = 0; a < 3; ++a) k |= uint64_t{(uint64_t{h.cell[a]} << h.level) >> b & 1} << (3 * b + a);
      key[i] = k;
    }
    std::stable_sort(waiting.begin(), waiting.end(), [&](size_t x, size_t y) { return key[x] < key[y]; });
    batch = std::max<size_t>(1, std::min(batch, waiting.size()) / 2);
    std::vector<size_t> again;
    for (size_t first = 0; first < waiting.size(); first += batch) {
      const size_t n = std::min(batch, waiting.size() - first);
      sub.resize(n);
      for (size_t k = 0; k < n; ++k) sub[k] = rays[waiting[first + k]];
      const std::vector<mv::RayHit> got = t.trace(sub, options, want_colours);
      account_passes(t, path, passes_, pages_streamed_);
      for (size_t k = 0; k < n; ++k) {
        out[waiting[first + k]] = got[k];  // a coarse hit too: where it stopped orders the next round
        if (want_colours) (*colours)[waiting[first + k]] = sub_colours[k];
        if (got[k].hit && got[k].coarse) again.push_back(waiting[first + k]);
      }
    }
    if (batch == 1 && again.size() == waiting.size())
      throw mv::capi::ApiError(MV_ERROR_OUT_OF_MEMORY, path + ": a single ray reads more pages than the cache's " +
                                                           std::to_string(t.cache()->config().slots) +
                                                           " slots (raise cache_memory= or memory=)");
    waiting = std::move(again);
  }
  return out;
}

size_t MvSceneTy::ray_batch_locked(size_t wanted) {
  mv::Tracer& t = tracer_locked();
  const mv::Device& dev = *device->device;
  const uint64_t free = budget_left(dev);
  const uint64_t keep = 4 * dev.page_bytes() + (t.paged() ? t.cache()->update_scratch_bytes() : 0);
  const uint64_t fit = free > keep ? (free - keep) / kRayDeviceBytes : 0;
  return static_cast<size_t>(std::clamp<uint64_t>(fit, 1, wanted));
}

MvSceneStats MvSceneTy::stats_locked() {
  MvSceneStats s{};
  s.byteSize = sizeof s;
  if (tracer_ && tracer_->paged() && tracer_->cache()->config().slots < tracer_->cache()->config().pages) {
    const mv::PageCacheConfig& c = tracer_->cache()->config();  // (a cache of every page, preloaded, is resident)
    s.paged = 1;
    s.cacheBytes = uint64_t{c.slots} * c.page_words * 4;
  }
  s.passes = passes_;
  s.pagesStreamed = pages_streamed_;
  s.peakDeviceBytes = peak_;
  return s;
}

void MvSceneTy::note_peak_locked() { peak_ = std::max(peak_, device->device->memory_peak()); }

MvSceneTy::~MvSceneTy() {
  if (!scratch.empty()) std::remove(scratch.c_str());
  if (!device) return;
  {
    std::lock_guard<std::recursive_mutex> g(device->lock);
    tracer_.reset();  // its buffers go back to the device's pool
  }
  mvReleaseDevice(device);
}
