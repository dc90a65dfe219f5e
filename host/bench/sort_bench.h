// `megavox bench sort`: our radix sort against the sorts a user would pick instead, in one run.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/device.h"
#include "megavox/primitives.h"

namespace mv::bench {

struct SortBenchOptions {
  uint64_t n = 16u << 20;
  int key_bits = 64;    // 32 or 64
  bool pairs = true;    // move a 32-bit value (the original index) with each key
  int repeats = 5;      // runs of megavox and of each baseline; the best of each is reported
  SortStrategy strategy = SortStrategy::Auto;
  uint64_t seed = 1;
};

// One CPU baseline on the same input as megavox.
struct SortBaselineRun {
  std::string name;       // "std::sort", "ips4o::parallel::sort", ...
  double seconds = 0;     // best of the repeats
  double keys_per_s = 0;
  double speedup = 0;     // megavox's speed over this one: seconds / megavox seconds
  bool verified = false;  // megavox's keys in order, each value naming an input record with its key, once
};

struct SortBenchResult {
  DeviceInfo device;
  uint64_t n = 0;
  int key_bits = 0;
  bool pairs = true;
  uint32_t passes = 0;
  std::string variant;           // what ran: "hybrid", "lsd" or "cooperative"
  double seconds = 0;            // best device sort, data already on the device
  double upload_seconds = 0;     // host -> device of keys (+ values), last run
  double download_seconds = 0;
  double keys_per_s = 0;
  double std_sort_seconds = 0;
  double std_sort_keys_per_s = 0;
  std::string parallel_sort_name;  // the faster of tbb::parallel_sort and boost block_indirect_sort
  double parallel_sort_seconds = 0;
  double parallel_sort_keys_per_s = 0;
  double speedup_vs_std_sort = 0;
  double speedup_vs_parallel_sort = 0;
  std::vector<SortBaselineRun> baselines;  // every baseline run: std::sort, tbb, boost, ips4o, vqsort (when built in)
  const SortBaselineRun* baseline(const std::string& name) const;  // null when it did not run
  double copy_gb_per_s = 0;      // host memcpy, bytes read + written per second, measured in this run
  double floor_bytes = 0;        // bytes the variant must move through memory (sort_bench.cpp)
  double floor_seconds = 0;      // floor_bytes / copy bandwidth
  double floor_fraction = 0;     // floor_seconds / seconds
  bool verified = false;         // output is the stable sort of the input (checked in full)
  std::vector<KernelTiming> kernel_totals;  // per kernel over the best run (with profiling)
  std::vector<std::string> missing_baselines;  // one line per baseline not built in (baselines/baselines.h)
};

// Throws mv::Error when the device cannot hold the data (the message says how much it needs).
SortBenchResult run_sort_bench(Device& dev, const SortBenchOptions& options);

// Host memcpy bandwidth (read + write bytes per second), best of a few copies of `bytes`.
double measure_copy_bandwidth(uint64_t bytes);

}  // namespace mv::bench
