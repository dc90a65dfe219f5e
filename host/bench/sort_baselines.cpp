#include "sort_baselines.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <span>
#include <type_traits>

#include "baselines.h"

#include "stopwatch.h"

namespace mv::bench {

namespace {

template <class Key>
using Pair = std::conditional_t<sizeof(Key) == 8, baseline::Pair64, baseline::Pair32>;

template <class Key>
struct ByKey {
  bool operator()(const Pair<Key>& a, const Pair<Key>& b) const { return a.key < b.key; }
};

// vqsort's packed form of a record (see baseline::vqsort): the key above its value in one wider word.
template <class Key>
using Packed = std::conditional_t<sizeof(Key) == 8, baseline::U128, uint64_t>;

template <class Key>
Packed<Key> pack(const Pair<Key>& p) {
  if constexpr (sizeof(Key) == 8) return {p.value, p.key};
  else return uint64_t{p.key} << 32 | p.value;
}

template <class Key>
Pair<Key> unpack(const Packed<Key>& w) {
  if constexpr (sizeof(Key) == 8) return {w.hi, static_cast<uint32_t>(w.lo)};
  else return {static_cast<uint32_t>(w >> 32), static_cast<uint32_t>(w)};
}

template <class Key>
class Runner {
 public:
  Runner(const std::vector<Key>& input, const std::vector<Key>& sorted, int repeats)
      : input_(input), sorted_(sorted), repeats_(std::max(1, repeats)), pairs_(input.size()) {}

  // Best of the repeats of `sort` on the records, each time loaded afresh from the input; `prepare` and
  // `finish` (outside the timing) move the records into and out of the form the sort takes.
  template <class Prepare, class Sort, class Finish>
  void time(const char* name, Prepare&& prepare, Sort&& sort, Finish&& finish) {
    double best = 1e30;
    for (int rep = 0; rep < repeats_; ++rep) {
      for (uint32_t i = 0; i < pairs_.size(); ++i) pairs_[i] = {input_[i], i};
      prepare();
      auto t0 = Clock::now();
      sort();
      best = std::min(best, since(t0));
      finish();
    }
    SortBaselineRun r;
    r.name = name;
    r.seconds = best;
    r.keys_per_s = double(pairs_.size()) / best;
    r.verified = same_as_megavox();
    runs_.push_back(r);
  }
  template <class Sort>
  void time(const char* name, Sort&& sort) {
    time(name, [] {}, sort, [] {});
  }

  std::vector<Pair<Key>>& pairs() { return pairs_; }
  std::vector<SortBaselineRun> take() { return std::move(runs_); }

 private:
  // The keys are megavox's, in order, and each value names an input record with that key, once: the same
  // sort up to the order of equal keys, which an unstable sort may choose (with unique keys: identical).
  bool same_as_megavox() const {
    std::vector<bool> seen(input_.size(), false);
    for (size_t i = 0; i < pairs_.size(); ++i) {
      const uint32_t v = pairs_[i].value;
      if (pairs_[i].key != sorted_[i] || v >= input_.size() || seen[v] || input_[v] != sorted_[i]) return false;
      seen[v] = true;
    }
    return true;
  }

  const std::vector<Key>& input_;
  const std::vector<Key>& sorted_;
  int repeats_;
  std::vector<Pair<Key>> pairs_;
  std::vector<SortBaselineRun> runs_;
};

}  // namespace

template <class Key>
std::vector<SortBaselineRun> run_sort_baselines(const std::vector<Key>& input, const std::vector<Key>& sorted,
                                                int repeats, std::vector<std::string>& missing) {
  Runner<Key> run(input, sorted, repeats);
  auto& pairs = run.pairs();
  run.time("std::sort", [&] { std::sort(pairs.begin(), pairs.end(), ByKey<Key>{}); });
  run.time("tbb::parallel_sort", [&] { tbb::parallel_sort(pairs.begin(), pairs.end(), ByKey<Key>{}); });
  auto built_in = [&](const baseline::Baseline& b) {
    if (!b.built_in) missing.push_back(baseline::missing_note(b));
    return b.built_in;
  };
  if (built_in(baseline::boost_sort()))
    run.time(baseline::boost_sort().name, [&] { baseline::block_indirect_sort(std::span(pairs)); });
  if (built_in(baseline::ips4o()))
    run.time(baseline::ips4o().name, [&] { baseline::ips4o_parallel_sort(std::span(pairs)); });
  if (built_in(baseline::vqsort())) {
    std::vector<Packed<Key>> packed(pairs.size());
    run.time(
        baseline::vqsort().name, [&] { std::transform(pairs.begin(), pairs.end(), packed.begin(), pack<Key>); },
        [&] { baseline::vqsort(std::span(packed)); },
        [&] { std::transform(packed.begin(), packed.end(), pairs.begin(), unpack<Key>); });
  }
  return run.take();
}

template std::vector<SortBaselineRun> run_sort_baselines(const std::vector<uint32_t>&, const std::vector<uint32_t>&,
                                                         int, std::vector<std::string>&);
template std::vector<SortBaselineRun> run_sort_baselines(const std::vector<uint64_t>&, const std::vector<uint64_t>&,
                                                         int, std::vector<std::string>&);

}  // namespace mv::bench
