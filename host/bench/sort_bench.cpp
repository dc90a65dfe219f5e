#include "sort_bench.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <map>

#include "baselines.h"
#include "megavox/error.h"
#include "megavox/primitives.h"
#include "sort_baselines.h"

#include "stopwatch.h"

namespace mv::bench {

namespace {


uint64_t splitmix64(uint64_t& state) {
  uint64_t z = (state += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// Sorted, a permutation of the input, and stable (equal keys keep their original order).
template <class Key>
bool verify(const std::vector<Key>& input, const std::vector<Key>& keys, const std::vector<uint32_t>& values,
            bool pairs) {
  size_t n = input.size();
  for (size_t i = 1; i < n; ++i)
    if (keys[i - 1] > keys[i]) return false;
  if (!pairs) {
    std::vector<Key> expect = input;
    std::sort(expect.begin(), expect.end());
    return expect == keys;
  }
  std::vector<bool> seen(n, false);
  for (size_t i = 0; i < n; ++i) {
    uint32_t v = values[i];
    if (v >= n || seen[v] || input[v] != keys[i]) return false;
    seen[v] = true;
    if (i > 0 && keys[i - 1] == keys[i] && values[i - 1] > v) return false;
  }
  return true;
}

template <class Key>
SortBenchResult run(Device& dev, const SortBenchOptions& o) {
  if (o.n == 0 || o.n > kMaxDeviceItems) throw Error("bench sort: --n must be in [1, 2^31-1]");
  const auto n = static_cast<uint32_t>(o.n);
  SortBenchResult r;
  r.device = dev.info();
  r.n = n;
  r.key_bits = sizeof(Key) * 8;
  r.pairs = o.pairs;

  std::vector<Key> input(n);
  uint64_t state = o.seed;
  for (auto& k : input) k = static_cast<Key>(splitmix64(state));
  std::vector<uint32_t> iota(n);
  for (uint32_t i = 0; i < n; ++i) iota[i] = i;

  const KeyBits bits = sizeof(Key) == 8 ? KeyBits::k64 : KeyBits::k32;
  Buffer keys = dev.alloc(uint64_t{n} * sizeof(Key), "benchmark keys");
  Buffer values = o.pairs ? dev.alloc(uint64_t{n} * 4, "benchmark values") : Buffer();
  double best = 1e30;
  for (int rep = 0; rep < std::max(1, o.repeats); ++rep) {
    auto t0 = Clock::now();
    dev.upload(keys, input.data(), uint64_t{n} * sizeof(Key));
    if (o.pairs) dev.upload(values, iota.data(), uint64_t{n} * 4);
    dev.finish();
    r.upload_seconds = since(t0);
    dev.take_timings();
    t0 = Clock::now();
    SortReport rep_report = radix_sort(dev, keys, o.pairs ? &values : nullptr, n, bits, o.strategy);
    dev.finish();
    double t = since(t0);
    auto timings = dev.take_timings();
    r.passes = rep_report.passes;
    r.variant = rep_report.cooperative ? "cooperative" : rep_report.hybrid ? "hybrid" : "lsd";
    if (t < best) {
      best = t;
      std::map<std::string, uint64_t> totals;
      for (auto& k : timings) totals[k.kernel] += k.ns;
      r.kernel_totals.clear();
      for (auto& [name, ns] : totals) r.kernel_totals.push_back({name, ns});
    }
  }
  r.seconds = best;
  std::vector<Key> out_keys(n);
  std::vector<uint32_t> out_values(o.pairs ? n : 0);
  auto t0 = Clock::now();
  dev.download(keys, out_keys.data(), uint64_t{n} * sizeof(Key));
  if (o.pairs) dev.download(values, out_values.data(), uint64_t{n} * 4);
  r.download_seconds = since(t0);
  r.verified = verify(input, out_keys, out_values, o.pairs);
  keys = Buffer();
  values = Buffer();

  // Baselines on the same input, as (key, value) structs: what a C++ user would write.
  r.baselines = run_sort_baselines(input, out_keys, o.repeats, r.missing_baselines);
  for (auto& b : r.baselines) b.speedup = b.seconds / r.seconds;
  const SortBaselineRun* std_sort = r.baseline("std::sort");
  r.std_sort_seconds = std_sort->seconds;
  for (const char* name : {"tbb::parallel_sort", baseline::boost_sort().name}) {
    const SortBaselineRun* b = r.baseline(name);
    if (b && (r.parallel_sort_name.empty() || b->seconds < r.parallel_sort_seconds)) {
      r.parallel_sort_name = b->name;
      r.parallel_sort_seconds = b->seconds;
    }
  }

  r.keys_per_s = n / r.seconds;
  r.std_sort_keys_per_s = n / r.std_sort_seconds;
  r.parallel_sort_keys_per_s = n / r.parallel_sort_seconds;
  r.speedup_vs_std_sort = r.std_sort_seconds / r.seconds;
  r.speedup_vs_parallel_sort = r.parallel_sort_seconds / r.seconds;
  const uint64_t pair_bytes = sizeof(Key) + (o.pairs ? 4 : 0);
  r.copy_gb_per_s = measure_copy_bandwidth(std::max<uint64_t>(uint64_t{n} * pair_bytes, 256u << 20)) / 1e9;
  // Bytes that must cross memory. LSD: every digit pass reads and writes each pair. Hybrid: the reduction reads
  // the keys, the global pass reads and writes the pairs, and each bucket is read and written once more (its
  // in-bucket passes run in cache).
  r.floor_bytes = r.variant == "hybrid" ? double(n) * (sizeof(Key) + 4.0 * pair_bytes)
                                        : double(r.passes) * 2.0 * n * pair_bytes;
  r.floor_seconds = r.floor_bytes / (r.copy_gb_per_s * 1e9);
  r.floor_fraction = r.floor_seconds / r.seconds;
  return r;
}

}  // namespace

const SortBaselineRun* SortBenchResult::baseline(const std::string& name) const {
  for (const auto& b : baselines)
    if (b.name == name) return &b;
  return nullptr;
}

double measure_copy_bandwidth(uint64_t bytes) {
  std::vector<char> a(bytes, 1), b(bytes, 2);  // touched, so page faults stay out of the timing
  double best = 1e30;
  for (int i = 0; i < 5; ++i) {
    auto t0 = Clock::now();
    std::memcpy(b.data(), a.data(), bytes);
    best = std::min(best, since(t0));
    std::swap(a, b);
  }
  return 2.0 * double(bytes) / best;
}

SortBenchResult run_sort_bench(Device& dev, const SortBenchOptions& options) {
  if (options.key_bits == 64) return run<uint64_t>(dev, options);
  if (options.key_bits == 32) return run<uint32_t>(dev, options);
  throw Error("bench sort: --key-bits must be 32 or 64");
}

}  // namespace mv::bench
