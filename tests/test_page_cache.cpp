// The page cache's update pass on every device against the plain reference (host/ref/cache_reference.h),
// state for state, and the notes' oracles (gigavoxels-cache.md 12): the LRU update is a stable partition, a
// slot used in the pass is never evicted while unused slots exist, requests are unique and stale stamps
// ignored, the page table and the slots stay consistent as slots are reused; fault injection: a failing
// producer, a one-page cache, a working set larger than the cache.
#include <algorithm>
#include <random>
#include <set>

#include "common/page_cache.h"
#include "cache/page_cache.h"
#include "cache_reference.h"
#include "test_support.h"

namespace mv::test {
namespace {

uint32_t page_word(uint32_t page, uint32_t j) { return (page * 0x9e3779b1u) ^ (j * 0x85ebca6bu + 1u); }

bool make_page(uint32_t page, std::span<uint32_t> words) {
  for (uint32_t j = 0; j < words.size(); ++j) words[j] = page_word(page, j);
  return true;
}

std::vector<uint32_t> fetch(Device& dev, const Buffer& b, uint64_t words) {
  std::vector<uint32_t> v(words);
  if (words) dev.download(b, v.data(), words * 4);
  return v;
}

void expect_maximal_runs(Device& dev, const PageCache& cache);
// The first page and the end of page pg's run, from its run word (runs here are shorter than the word's caps).
uint32_t run_first(uint32_t word, uint32_t pg) { return pg - MV_CACHE_RUN_BEFORE(word); }
uint32_t run_end(uint32_t word, uint32_t pg) { return pg + MV_CACHE_RUN_FROM(word); }

// One device cache and its reference, driven by the same passes: each pass writes the same usage and
// request stamps into both (standing in for the traversal), then both update.
struct Harness {
  Device& dev;
  PageCacheConfig cfg;
  PageCache cache;
  ref::CacheState ref;

  Harness(Device& d, PageCacheConfig c)
      : dev(d), cfg(c), cache(d, c), ref(ref::cache_init(c.slots, c.pages, c.page_words)) {}

  std::pair<CacheUpdateStats, ref::CacheStep> pass(const std::vector<uint32_t>& used_slots,
                                                   const std::vector<uint32_t>& asked_pages,
                                                   const PageProducer& produce = make_page) {
    const uint32_t t = cache.begin_pass();
    for (uint32_t s : used_slots) ref.usage[s] = t;
    for (uint32_t pg : asked_pages) ref.requests[pg] = t;
    dev.upload(cache.usage(), ref.usage.data(), ref.usage.size() * 4);
    dev.upload(cache.requests(), ref.requests.data(), ref.requests.size() * 4);
    CacheUpdateStats st = cache.update(produce);
    ref::CacheStep step = ref::cache_update(ref, t, cfg.max_loads, produce);
    return {st, step};
  }

  // A view that needs the pages of [first, first + count): it uses the slots of the resident ones, asks for
  // the missing ones (each asked several times, as many rays would) and, to test the filter, some resident ones.
  std::pair<CacheUpdateStats, ref::CacheStep> view(uint32_t first, uint32_t count, std::mt19937& rng,
                                                   const PageProducer& produce = make_page) {
    std::vector<uint32_t> used, asked;
    for (uint32_t pg = first; pg < first + count && pg < cfg.pages; ++pg) {
      if (ref.table[pg] != ref::kCacheNone) {
        used.push_back(ref.table[pg]);
        if (rng() % 8 == 0) asked.push_back(pg);
      } else {
        asked.insert(asked.end(), 1 + rng() % 3, pg);
      }
    }
    std::shuffle(asked.begin(), asked.end(), rng);
    return pass(used, asked, produce);
  }

  // Every device buffer equals the reference's, and the state is consistent: lru a permutation of the slots,
  // table and owners each other's inverse, every resident page's slot holding that page's words.
  void expect_same_and_consistent() {
    const auto table = fetch(dev, cache.table(), cfg.pages);
    const auto owner = fetch(dev, cache.owners(), cfg.slots);
    const auto lru = fetch(dev, cache.lru(), cfg.slots);
    const auto data = fetch(dev, cache.data(), uint64_t{cfg.slots} * cfg.page_words);
    ASSERT_EQ(lru, ref.lru);
    ASSERT_EQ(table, ref.table);
    ASSERT_EQ(owner, ref.owner);
    const auto all = fetch(dev, cache.table(), uint64_t{cache.runs_at()} + cfg.pages);
    for (uint32_t pg = 0; pg < cfg.pages; ++pg)  // runs: a missing page's word is never read
      if (table[pg] != MV_CACHE_NONE) ASSERT_EQ(all[cache.runs_at() + pg], ref.runs[pg]) << "page " << pg << "'s run";
    ASSERT_EQ(data, ref.data);
    std::vector<uint32_t> sorted = lru;
    std::sort(sorted.begin(), sorted.end());
    for (uint32_t s = 0; s < cfg.slots; ++s) ASSERT_EQ(sorted[s], s);
    uint32_t resident = 0;
    for (uint32_t pg = 0; pg < cfg.pages; ++pg) {
      if (table[pg] == MV_CACHE_NONE) continue;
      ++resident;
      ASSERT_LT(table[pg], cfg.slots);
      ASSERT_EQ(owner[table[pg]], pg) << "page " << pg;
      for (uint32_t j = 0; j < cfg.page_words; ++j)
        ASSERT_EQ(data[uint64_t{table[pg]} * cfg.page_words + j], page_word(pg, j)) << "page " << pg;
    }
    for (uint32_t s = 0; s < cfg.slots; ++s)
      if (owner[s] != MV_CACHE_NONE) {
        ASSERT_EQ(table[owner[s]], s) << "slot " << s;
        --resident;
      }
    ASSERT_EQ(resident, 0u);
    expect_maximal_runs(dev, cache);
  }
};

// Runs oracle: each resident page's run holds it, continues exactly while the next page sits in the next slot,
// and starts exactly where the previous page does not precede it (so runs are maximal and disjoint).
void expect_maximal_runs(Device& dev, const PageCache& cache) {
  const uint32_t pages = cache.config().pages, at = cache.runs_at();
  const auto all = fetch(dev, cache.table(), uint64_t{at} + pages);
  auto continues = [&](uint32_t pg) {  // resident page pg follows pg - 1 in the slots
    return pg > 0 && all[pg] != MV_CACHE_NONE && all[pg - 1] != MV_CACHE_NONE && all[pg] == all[pg - 1] + 1;
  };
  for (uint32_t pg = 0; pg < pages; ++pg) {
    if (all[pg] == MV_CACHE_NONE) continue;
    const uint32_t first = run_first(all[at + pg], pg), end = run_end(all[at + pg], pg);
    ASSERT_LE(first, pg) << "page " << pg;
    ASSERT_LT(pg, end) << "page " << pg;
    if (continues(pg)) {
      ASSERT_EQ(first, run_first(all[at + pg - 1], pg - 1)) << "page " << pg;
      ASSERT_EQ(end, run_end(all[at + pg - 1], pg - 1)) << "page " << pg;
    } else {
      ASSERT_EQ(first, pg) << "page " << pg;
    }
    if (pg + 1 == pages || !continues(pg + 1)) ASSERT_EQ(end, pg + 1) << "page " << pg;
  }
}

void expect_same_stats(const CacheUpdateStats& st, const ref::CacheStep& step, uint32_t slots) {
  EXPECT_EQ(st.requested, step.requested);
  EXPECT_EQ(st.loaded, step.loaded);
  EXPECT_EQ(st.failed, step.failed);
  EXPECT_EQ(st.evicted, step.evicted);
  EXPECT_EQ(st.dropped, step.dropped);
  EXPECT_EQ(st.used_slots, slots - step.unused);
  EXPECT_EQ(st.over_capacity, step.requested > step.unused);
}

class PageCacheTest : public ::testing::TestWithParam<DeviceInfo> {
 protected:
  Device& dev() { return shared_device(GetParam()); }
};

// LRU oracle: after each update the list is a permutation with the slots unused in the pass first and the
// used ones after, each side in the order it had before (checked on the device's lists themselves).
TEST_P(PageCacheTest, LruUpdateIsAStablePartition) {
  Harness h(dev(), {1000, 1000, 2, 0, {}});
  std::mt19937 rng(7);
  std::vector<uint32_t> before = fetch(dev(), h.cache.lru(), 1000);
  for (int pass = 0; pass < 12; ++pass) {
    std::vector<uint32_t> used;
    for (uint32_t s = 0; s < 1000; ++s)
      if (rng() % (pass % 3 == 0 ? 2 : 9) == 0) used.push_back(s);
    if (pass == 5) used.clear();                                       // nothing used
    if (pass == 6) for (uint32_t s = 0; s < 1000; ++s) used.push_back(s);  // everything used
    auto [st, step] = h.pass(used, {});
    const auto lru = fetch(dev(), h.cache.lru(), 1000);
    const auto usage = fetch(dev(), h.cache.usage(), 1000);
    const uint32_t t = h.cache.stamp();
    std::set<uint32_t> used_set(used.begin(), used.end());
    ASSERT_EQ(st.used_slots, used_set.size());
    for (uint32_t i = 0; i < 1000; ++i) ASSERT_EQ(usage[lru[i]] == t, i >= 1000 - st.used_slots) << "position " << i;
    std::vector<uint32_t> unused_before, used_before;
    for (uint32_t s : before) (used_set.count(s) ? used_before : unused_before).push_back(s);
    ASSERT_TRUE(std::equal(unused_before.begin(), unused_before.end(), lru.begin()));
    ASSERT_TRUE(std::equal(used_before.begin(), used_before.end(), lru.begin() + unused_before.size()));
    ASSERT_EQ(lru, h.ref.lru);
    EXPECT_EQ(st.requested, 0u);
    before = lru;
  }
}

// Request oracle: the list holds each missing page asked for in this pass once, in page order; pages asked
// for in an earlier pass (stale stamps, never cleared) and resident pages are not in it.
TEST_P(PageCacheTest, RequestsAreUniqueAndStaleStampsIgnored) {
  Harness h(dev(), {64, 9000, 1, 0, {}});
  std::mt19937 rng(11);
  auto [st1, step1] = h.view(100, 40, rng);  // 40 pages resident
  ASSERT_EQ(st1.loaded, 40u);
  std::vector<uint32_t> asked;
  for (int k = 0; k < 500; ++k) asked.push_back(rng() % 9000);
  for (uint32_t pg = 100; pg < 140; ++pg) asked.push_back(pg);  // resident: no request
  asked.insert(asked.end(), asked.begin(), asked.begin() + 200);  // repeats
  // stale stamps: pages asked for in pass 1 that this pass does not ask for
  auto [st, step] = h.pass({}, asked);
  std::set<uint32_t> want;
  for (uint32_t pg : asked)
    if (pg < 100 || pg >= 140) want.insert(pg);
  ASSERT_EQ(st.requested, want.size());
  const auto list = fetch(dev(), h.cache.request_list(), st.requested);
  ASSERT_TRUE(std::equal(want.begin(), want.end(), list.begin()));
  // the first 24 get slots: the 40 pages loaded for this pass count as used by it
  EXPECT_EQ(st.used_slots, 40u);
  EXPECT_EQ(st.loaded, 24u);
  EXPECT_EQ(st.dropped, st.requested - 24u);
  EXPECT_TRUE(st.over_capacity);
  expect_same_stats(st, step, h.cfg.slots);
  h.expect_same_and_consistent();
  // a pass that asks for nothing: no requests, whatever the older stamps say
  auto [st3, step3] = h.pass({}, {});
  EXPECT_EQ(st3.requested, 0u);
  EXPECT_EQ(st3.loaded, 0u);
}

// Read-ahead's list: the missing pages asked for so far in the pass, each once, in page order, capped; the same
// whether the host reads the stamps in place or the request kernels compact them.
TEST_P(PageCacheTest, MissingSoFarListsTheUpdatesRequests) {
  Harness h(dev(), {64, 9000, 1, 0, {}});
  std::mt19937 rng(12);
  h.view(100, 40, rng);  // 40 pages resident
  std::vector<uint32_t> asked;
  for (int k = 0; k < 300; ++k) asked.push_back(rng() % 9000);
  for (uint32_t pg = 100; pg < 140; ++pg) asked.push_back(pg);  // resident: not missing
  const uint32_t t = h.cache.begin_pass();
  for (uint32_t pg : asked) h.ref.requests[pg] = t;
  dev().upload(h.cache.requests(), h.ref.requests.data(), h.ref.requests.size() * 4);
  std::set<uint32_t> want;
  for (uint32_t pg : asked)
    if (pg < 100 || pg >= 140) want.insert(pg);
  for (bool in_place : {true, false}) {
    SCOPED_TRACE(in_place ? "in place" : "on the device");
    const std::vector<uint32_t> all = h.cache.missing_so_far(100000, in_place);
    ASSERT_EQ(all.size(), want.size());
    EXPECT_TRUE(std::equal(want.begin(), want.end(), all.begin()));
    const std::vector<uint32_t> capped = h.cache.missing_so_far(17, in_place);
    ASSERT_EQ(capped.size(), 17u);
    EXPECT_TRUE(std::equal(capped.begin(), capped.end(), all.begin()));
  }
  const CacheUpdateStats st = h.cache.update(make_page);  // the update lists the same pages
  EXPECT_EQ(st.requested, want.size());
}

// Eviction safety: a slot used in the pass keeps its page while unused slots exist; when the requests outnumber
// the unused slots (a working set larger than the cache), only the unused slots are reused and the rest of
// the requests wait (dropped, over_capacity), so no page a pass used disappears under it.
TEST_P(PageCacheTest, UsedSlotsAreNeverEvicted) {
  Harness h(dev(), {100, 2000, 3, 0, {}});
  std::mt19937 rng(3);
  for (int pass = 0; pass < 25; ++pass) {
    const uint32_t width = pass % 5 == 4 ? 300 : 30 + rng() % 80;  // sometimes 3x the cache
    const auto table_before = h.ref.table;
    auto [st, step] = h.view(rng() % 1700, width, rng);
    expect_same_stats(st, step, h.cfg.slots);
    const auto usage = fetch(dev(), h.cache.usage(), 100);
    for (uint32_t slot : step.victims) ASSERT_NE(usage[slot], h.cache.stamp()) << "pass " << pass;
    const auto table = fetch(dev(), h.cache.table(), 2000);
    for (uint32_t pg = 0; pg < 2000; ++pg) {
      if (table_before[pg] != MV_CACHE_NONE && usage[table_before[pg]] == h.cache.stamp()) {
        ASSERT_EQ(table[pg], table_before[pg]) << "page " << pg << " was used and lost its slot";
      }
    }
    if (width == 300) {
      EXPECT_TRUE(st.over_capacity);
      EXPECT_GT(st.dropped, 0u);
    }
    h.expect_same_and_consistent();
  }
}

// Page-table coherence as slots are reused many times: random views over a page range much larger than the
// cache, a producer failing now and then, with and without a per-update load cap; sizes past one scan block.
TEST_P(PageCacheTest, PageTableStaysConsistentAfterSlotReuse) {
  for (PageCacheConfig cfg : {PageCacheConfig{257, 5000, 5, 0, {}}, PageCacheConfig{257, 5000, 5, 7, {}},
                              PageCacheConfig{4099, 70001, 1, 0, {}}}) {
    SCOPED_TRACE(std::to_string(cfg.slots) + " slots, " + std::to_string(cfg.pages) + " pages, cap " +
                 std::to_string(cfg.max_loads));
    Harness h(dev(), cfg);
    std::mt19937 rng(cfg.slots + cfg.max_loads);
    uint32_t at = 0;
    for (int pass = 0; pass < 30; ++pass) {
      at = (at + rng() % (cfg.slots / 2)) % cfg.pages;  // a drifting view with overlap
      const uint32_t stamp = h.cache.stamp() + 1;
      PageProducer flaky = [stamp](uint32_t pg, std::span<uint32_t> w) {
        return (pg * 2654435761u + stamp) % 10 != 0 && make_page(pg, w);
      };
      auto [st, step] = h.view(at, cfg.slots / 2 + rng() % cfg.slots, rng, flaky);
      expect_same_stats(st, step, h.cfg.slots);
      EXPECT_EQ(st.bytes_uploaded, uint64_t{step.loaded + step.failed} * cfg.page_words * 4);
      if (cfg.max_loads) {
        EXPECT_LE(st.loaded + st.failed, cfg.max_loads);
      }
      h.expect_same_and_consistent();
    }
  }
}

// A producer that fails (returns false or throws): the pages stay missing, their slots free, the failure is
// counted and the first message kept; the next pass asks again and a working producer loads them.
TEST_P(PageCacheTest, FailingProducerLeavesPagesMissing) {
  Harness h(dev(), {16, 100, 4, 0, {}});
  std::mt19937 rng(5);
  auto [st0, step0] = h.view(0, 10, rng);
  ASSERT_EQ(st0.loaded, 10u);
  h.pass({}, {});  // pages 0-9 count as used by this pass (loaded for it): now behind the free slots
  PageProducer broken = [](uint32_t pg, std::span<uint32_t>) -> bool {
    if (pg % 2) throw Error("read failed at byte 4096");
    return false;
  };
  auto [st, step] = h.view(50, 12, rng, broken);  // no slot used in this pass
  EXPECT_EQ(st.requested, 12u);
  EXPECT_EQ(st.loaded, 0u);
  EXPECT_EQ(st.failed, 12u);
  EXPECT_EQ(st.evicted, 6u);  // 6 free slots first, then 6 of the pages 0-9
  EXPECT_NE(st.first_error.find("read failed at byte 4096"), std::string::npos) << st.first_error;
  expect_same_stats(st, step, h.cfg.slots);
  h.expect_same_and_consistent();
  const auto table = fetch(dev(), h.cache.table(), 100);
  for (uint32_t pg = 50; pg < 62; ++pg) EXPECT_EQ(table[pg], MV_CACHE_NONE);
  auto [st2, step2] = h.view(50, 12, rng);
  EXPECT_EQ(st2.loaded, 12u);
  EXPECT_EQ(st2.failed, 0u);
  h.expect_same_and_consistent();
}

// A one-page cache: each update loads at most one page, never while the pass used the slot; the view's
// other pages wait (over capacity), so a deeper page replaces a coarser one only in a pass that did not use it.
TEST_P(PageCacheTest, OnePageCache) {
  Harness h(dev(), {1, 10, 8, 0, {}});
  auto [a, sa] = h.pass({}, {3, 1, 2});
  EXPECT_EQ(a.loaded, 1u);
  EXPECT_TRUE(a.over_capacity);
  EXPECT_EQ(a.dropped, 2u);
  h.expect_same_and_consistent();
  EXPECT_EQ(fetch(dev(), h.cache.table(), 10)[1], 0u);  // the first in page order
  auto [b, sb] = h.pass({0}, {2, 3});                    // slot used: nothing evicted
  EXPECT_EQ(b.loaded, 0u);
  EXPECT_EQ(b.evicted, 0u);
  EXPECT_EQ(b.dropped, 2u);
  auto [c, sc] = h.pass({}, {2});
  EXPECT_EQ(c.loaded, 1u);
  EXPECT_EQ(c.evicted, 1u);
  h.expect_same_and_consistent();
  EXPECT_EQ(fetch(dev(), h.cache.table(), 10)[2], 0u);
}

// Preload (a slot for every page): the pages go into the slots in page order, batch by batch, so the table is
// one run; a page the producer fails (in the last batch: a later batch would take its free slot) splits it and
// stays missing until asked for, then takes the one free slot.
TEST_P(PageCacheTest, PreloadFillsTheSlotsInPageOrder) {
  PageCache c(dev(), {300, 300, 4, 0, {}});
  auto failing = [](uint32_t page, std::span<uint32_t> words) { return page != 290 && make_page(page, words); };
  const CacheUpdateStats st = c.preload(failing, 64);  // 5 batches
  EXPECT_EQ(st.loaded, 299u);
  EXPECT_EQ(st.failed, 1u);
  EXPECT_EQ(st.evicted, 0u);
  auto all = fetch(dev(), c.table(), c.runs_at() + 300ull);
  for (uint32_t pg = 0; pg < 300; ++pg) {
    if (pg == 290) {
      EXPECT_EQ(all[pg], MV_CACHE_NONE);
      continue;
    }
    ASSERT_EQ(all[pg], pg);
    ASSERT_EQ(run_first(all[c.runs_at() + pg], pg), pg < 290 ? 0u : 291u) << "page " << pg;
    ASSERT_EQ(run_end(all[c.runs_at() + pg], pg), pg < 290 ? 290u : 300u) << "page " << pg;
  }
  expect_maximal_runs(dev(), c);
  const uint32_t t = c.begin_pass();
  dev().upload(c.requests(), &t, 4, 290 * 4);
  const CacheUpdateStats again = c.update(make_page);
  EXPECT_EQ(again.loaded, 1u);
  EXPECT_EQ(again.evicted, 0u);
  all = fetch(dev(), c.table(), c.runs_at() + 300ull);
  EXPECT_EQ(all[290], 290u);
  for (uint32_t pg = 0; pg < 300; ++pg) ASSERT_EQ(all[c.runs_at() + pg], mv_cache_run_word(0, 300, pg)) << "page " << pg;
  const auto data = fetch(dev(), c.data(), 300ull * 4);
  for (uint32_t pg = 0; pg < 300; ++pg)
    for (uint32_t j = 0; j < 4; ++j) ASSERT_EQ(data[pg * 4 + j], page_word(pg, j));
  PageCache big(dev(), {70000, 70000, 1, 0, {}});  // a run longer than a run word counts: capped at 0xffff
  EXPECT_EQ(big.preload(make_page, 70000).loaded, 70000u);
  all = fetch(dev(), big.table(), big.runs_at() + 70000ull);
  EXPECT_EQ(all[big.runs_at()], 0xffffu);
  EXPECT_EQ(all[big.runs_at() + 35000], (35000u << 16) | 35000u);
  EXPECT_EQ(all[big.runs_at() + 69999], (0xffffu << 16) | 1u);
  PageCache smaller(dev(), {299, 300, 4, 0, {}});  // no slot for every page: nothing preloaded
  EXPECT_EQ(smaller.preload(make_page).loaded, 0u);
  EXPECT_EQ(smaller.stamp(), 0u);
}

TEST_P(PageCacheTest, BadConfigurationsAreClearErrors) {
  std::string msg = error_message([&] { PageCache(dev(), {0, 10, 4, 0, {}}); });
  EXPECT_NE(msg.find("at least 1"), std::string::npos) << msg;
  msg = error_message([&] { PageCache(dev(), {1u << 20, 10, 1u << 12, 0, {}}); });
  EXPECT_NE(msg.find("words one device call"), std::string::npos) << msg;
  auto small = Device::open({GetParam().selector(), 4u << 20, false});
  msg = error_message([&] { PageCache(*small, {512, 10, 4096, 0, {}}); });  // 8 MiB of slots
  EXPECT_NE(msg.find("page cache slots"), std::string::npos) << msg;
  PageCache c(dev(), {4, 4, 1, 0, {}});
  msg = error_message([&] { c.update(make_page); });
  EXPECT_NE(msg.find("before the first pass"), std::string::npos) << msg;
}

MV_INSTANTIATE_ON_ALL_DEVICES(PageCacheTest);

}  // namespace
}  // namespace mv::test
