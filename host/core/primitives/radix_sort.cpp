// Host side of the stable radix sort (kernels: kernels/common/radix_sort_body.h).
#include "common/radix_sort.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <thread>
#include <utility>

#include "primitives/chunking.h"
#include "primitives/launch_shape.h"
#include "megavox/error.h"
#include "megavox/primitives.h"
#include "primitives/scan_plan.h"

namespace mv {

namespace {

template <class Key>
uint64_t varying_bits(Device& dev, const Buffer& red, uint32_t blocks) {
  std::vector<Key> r(size_t{blocks} * 2);
  dev.download(red, r.data(), r.size() * sizeof(Key));
  Key acc_or = 0, acc_and = ~Key{0};
  for (uint32_t b = 0; b < blocks; ++b) {
    acc_or |= r[2 * b];
    acc_and &= r[2 * b + 1];
  }
  return acc_or ^ acc_and;  // a bit is constant over all keys iff OR and AND agree on it
}

// The lowest bit of each 8-bit digit an LSD sort passes over, least significant first: each digit starts at the
// lowest varying bit the digits below it leave, so constant bits cost nothing, wherever they lie.
std::vector<uint32_t> lsd_shifts(uint64_t varying) {
  std::vector<uint32_t> shifts;
  for (uint32_t b = 0; b < 64 && (varying >> b) != 0; b += MV_RADIX_BITS) {
    b += static_cast<uint32_t>(std::countr_zero(varying >> b));
    shifts.push_back(b);
  }
  return shifts;
}

// One sort: the kernels, buffers and shape shared by its passes.
struct SortRun {
  Device& dev;
  BlockShape shape;
  MvRadixParams p;
  Kernel& histogram;
  Kernel& scatter;
  Buffer& hist;  // blocks x 256 counts, the scan total, the hybrid's bucket counter
  ScanPlan scan;

  // histogram + scan of the digit at `shift` of `keys`: hist then holds each (digit, block)'s first output position.
  void count(const Buffer& keys, uint32_t shift) {
    p.shift = shift;
    dev.dispatch(histogram, shape.groups, shape.local_size, {&keys, &hist}, p);
    dev.barrier();
  }
  void scan_and_scatter(const Buffer& kin, Buffer& kout, const Buffer* vin, Buffer* vout) {
    record_scan(dev, scan, hist, hist);
    dev.dispatch(scatter, shape.groups, shape.local_size, {&kin, &kout, vin ? vin : &kin, vout ? vout : &kout, &hist},
                 p);
    dev.barrier();
  }
};

// Sizes of the counted digit's buckets (the counts are read back: one wait).
std::vector<uint64_t> bucket_sizes(Device& dev, const Buffer& hist, uint32_t blocks) {
  std::vector<uint32_t> h(size_t{blocks} * MV_RADIX_BUCKETS);
  dev.download(hist, h.data(), h.size() * 4);
  std::vector<uint64_t> sizes(MV_RADIX_BUCKETS, 0);
  for (uint32_t d = 0; d < MV_RADIX_BUCKETS; ++d)
    for (uint32_t b = 0; b < blocks; ++b) sizes[d] += h[size_t{d} * blocks + b];
  return sizes;
}

// Cuts the buckets into at most `ranges` ranges of about equal key counts: the ends of the ranges (buckets).
std::vector<uint32_t> bucket_ranges(const std::vector<uint64_t>& sizes, uint64_t n, uint32_t ranges) {
  std::vector<uint32_t> ends;
  uint64_t acc = 0;
  for (uint32_t d = 0; d < MV_RADIX_BUCKETS; ++d) {
    acc += sizes[d];
    if (acc * ranges >= n * (ends.size() + 1) && d + 1 < MV_RADIX_BUCKETS) ends.push_back(d + 1);
  }
  ends.push_back(MV_RADIX_BUCKETS);
  return ends;
}

// Device memory the passes allocate: scratch copies of keys and values, the histograms and their scan, in whole
// pages as the pool hands them out.
uint64_t scratch_bytes(Device& dev, uint64_t hist, uint64_t n, uint64_t key_bytes, bool values) {
  const uint64_t page = dev.page_bytes();
  auto pages = [&](uint64_t bytes) { return (bytes + page - 1) / page * page; };
  return pages(n * key_bytes) + (values ? pages(n * 4) : 0) + pages((hist + 2) * 4) +
         pages((uint64_t{block_shape(dev.info(), hist).blocks} + 1) * 8);
}

// The hybrid's second stage over the buckets [first, end): the global pass left 256 buckets in kin / vin; each is
// sorted there on the bits [low, top), moving through scratch slices of kout / vout. With no loop cap a few
// work-items (two per compute unit) each take bucket after bucket through one slice of the largest bucket's size,
// which stays in cache; under a cap every bucket gets its own work-item and works through its own range.
void sort_buckets(SortRun& run, const Buffer& kin, Buffer& kout, const Buffer* vin, Buffer* vout, uint32_t top,
                  uint32_t low, uint32_t largest, Kernel& local_sort, uint32_t first, uint32_t end) {
  const DeviceInfo& info = run.dev.info();
  run.p.local_top = top;
  run.p.local_low = low;
  run.p.bucket_first = first;
  run.p.bucket_end = end;
  uint32_t items = end - first;
  run.p.scratch_stride = 0;
  if (info.max_loop_iterations == 0 && run.p.n / largest >= 2) {
    items = std::min({items, 2 * std::max(1u, info.compute_units), run.p.n / largest});
    run.p.scratch_stride = largest;
    // the bucket counter (after the histograms and the scan total) starts at the range
    run.dev.fill(run.hist, first, 4, (uint64_t{run.p.blocks} * MV_RADIX_BUCKETS + 1) * 4);
    run.dev.barrier();
  }
  const uint32_t local = run.shape.local_size;
  run.dev.dispatch(local_sort, (items + local - 1) / local, local,
                   {&kin, &kout, vin ? vin : &kin, vout ? vout : &kout, &run.hist}, run.p);
  run.dev.barrier();
}

// Shared memory of the cooperative scatter (radix_coop_scatter.h) with 64-bit keys.
constexpr uint64_t kCoopSharedBytes = MV_COOP_TILE * 12 + (MV_COOP_COUNTERS + MV_COOP_AUX) * 4;

// The cooperative variant's shape: work-groups of MV_COOP_WG items, one block of MV_COOP_BLOCK keys each (a
// work-group takes several where the device's group count is smaller).
BlockShape coop_shape(const DeviceInfo& info, uint64_t n) {
  BlockShape s;
  s.blocks = static_cast<uint32_t>((n + MV_COOP_BLOCK - 1) / MV_COOP_BLOCK);
  s.block_size = MV_COOP_BLOCK;
  s.local_size = MV_COOP_WG;
  s.groups = std::min(s.blocks, std::max(1u, info.max_groups));
  return s;
}

}  // namespace

bool cooperative_sort_fits(const DeviceInfo& info) {
  return info.max_work_group_size >= MV_COOP_WG && info.local_memory_bytes >= kCoopSharedBytes;
}

bool prefers_cooperative_sort(const DeviceInfo& info) {
  // GPUs: thousands of work-items, which only shared tiles keep busy. Not lavapipe, though its SIMD lanes are
  // lock-step: there the cooperative passes measured 2.5x slower than one block per work-item (1M pairs:
  // scatter 1.57 s against 0.62 s), its shared-memory accesses and barriers costing more than they save.
  return info.massively_parallel && cooperative_sort_fits(info);
}

namespace {

SortReport sort_on_device(Device& dev, Buffer& keys, Buffer* values, uint64_t n, KeyBits bits, SortStrategy strategy,
                          const SortedPrefix* on_prefix, uint32_t ranges, uint32_t payload_bits = 0) {
  SortReport report;
  if (n <= 1) return report;
  detail::check_device_items("radix_sort", n);
  const bool k64 = bits == KeyBits::k64;
  const uint32_t key_bits = k64 ? 64 : 32;
  const uint64_t key_bytes = key_bits / 8;
  if (keys.bytes() < n * key_bytes || (values && values->bytes() < n * 4))
    throw Error("radix_sort: buffers too small for " + std::to_string(n) + " keys");

  const DeviceInfo& info = dev.info();
  BlockShape s = block_shape(info, n);
  Kernel& or_and = dev.kernel(k64 ? KernelId::radix_or_and_k64 : KernelId::radix_or_and_k32);
  const bool coop = strategy == SortStrategy::Cooperative ||
                    (strategy == SortStrategy::Auto && prefers_cooperative_sort(info));
  if (coop && !cooperative_sort_fits(info))
    throw Error("radix_sort: device " + info.name + " cannot run the cooperative sort (it needs work-groups of " +
                std::to_string(MV_COOP_WG) + " items and " + format_bytes(kCoopSharedBytes) + " of shared memory)");
  const bool may_hybrid = !coop && (strategy == SortStrategy::Hybrid ||
                                    (strategy == SortStrategy::Auto && !info.massively_parallel));
  const BlockShape pass_shape = coop ? coop_shape(info, n) : s;  // the digit passes' shape
  // The block passes scatter through line buffers with streaming stores (3x faster on PoCL: 16M pairs 0.155 s
  // -> 0.046 s), except under a loop cap, where the buffers' flush loops would count against it.
  const bool stream = !coop && info.max_loop_iterations == 0;

  Buffer red = dev.alloc(uint64_t{s.blocks} * 2 * key_bytes, "radix sort key reduction");
  const uint64_t hist_words = uint64_t{std::max(s.blocks, pass_shape.blocks)} * MV_RADIX_BUCKETS;
  Buffer hist = dev.alloc((hist_words + 2) * 4, "radix sort histograms");  // + the scan total, the bucket counter
  MvRadixParams p{static_cast<uint32_t>(n), s.blocks, s.block_size, 0, values ? 1u : 0u, 0, 0, 0, 0,
                  0, MV_RADIX_BUCKETS};
  // Where the hybrid may run, the reduction also counts the top digit: random keys vary there, and the global
  // pass then needs no histogram pass of its own. Not under a loop cap, where a private histogram is slow.
  if (may_hybrid && info.max_loop_iterations == 0) {
    p.count = 1;
    p.shift = key_bits - MV_RADIX_BITS;
  }
  dev.dispatch(or_and, s.groups, s.local_size, {&keys, &red, &hist}, p);
  dev.barrier();
  uint64_t varying = k64 ? varying_bits<uint64_t>(dev, red, s.blocks) : varying_bits<uint32_t>(dev, red, s.blocks);
  if (payload_bits) varying &= ~uint64_t{0} << payload_bits;  // the payload is carried, not sorted

  for (uint32_t d = 0; d < key_bits / MV_RADIX_BITS; ++d)
    if (((varying >> (MV_RADIX_BITS * d)) & 0xff) == 0) ++report.digits_skipped;
  if (varying == 0) return report;
  const uint32_t low = static_cast<uint32_t>(std::countr_zero(varying));
  const uint32_t high = 63u - static_cast<uint32_t>(std::countl_zero(varying));

  // Name the whole need up front rather than the first scratch buffer that fails.
  const uint64_t scratch = scratch_bytes(dev, hist_words, n, key_bytes, values != nullptr);
  if (scratch > detail::memory_left(dev, false) && scratch > detail::memory_left(dev, true))
    throw DeviceMemoryError("radix_sort: " + std::to_string(n) + " keys need " + format_bytes(scratch) +
                            " of device scratch beside their data, but " +
                            format_bytes(detail::memory_left(dev, false)) + " of the budget " +
                            format_bytes(dev.memory_budget()) +
                            " is left; raise the device memory budget, or sort host vectors (they run in pieces that fit)");

  const bool counted_top = p.count != 0;
  p.count = 0;
  p.blocks = pass_shape.blocks;
  p.block_size = pass_shape.block_size;
  SortRun run{dev,
              pass_shape,
              p,
              dev.kernel(coop ? (k64 ? KernelId::radix_coop_histogram_k64 : KernelId::radix_coop_histogram_k32)
                              : (k64 ? KernelId::radix_histogram_k64 : KernelId::radix_histogram_k32)),
              dev.kernel(coop     ? (k64 ? KernelId::radix_coop_scatter_k64 : KernelId::radix_coop_scatter_k32)
                         : stream ? (k64 ? KernelId::radix_scatter_stream_k64 : KernelId::radix_scatter_stream_k32)
                                  : (k64 ? KernelId::radix_scatter_k64 : KernelId::radix_scatter_k32)),
              hist,
              plan_scan(dev, uint64_t{pass_shape.blocks} * MV_RADIX_BUCKETS)};
  report.cooperative = coop;
  Buffer keys_alt = dev.alloc(n * key_bytes, "radix sort scratch keys");
  Buffer values_alt = values ? dev.alloc(n * 4, "radix sort scratch values") : Buffer();

  // The hybrid's global digit: the top 8 varying bits. More than one digit must vary for it to pay.
  const uint32_t msd = high >= low + MV_RADIX_BITS ? high + 1 - MV_RADIX_BITS : low;
  bool hybrid = may_hybrid && msd > low;
  uint32_t largest = 0;
  std::vector<uint64_t> sizes;
  if (hybrid) {
    if (counted_top && msd == key_bits - MV_RADIX_BITS) run.p.shift = msd;
    else run.count(keys, msd);
    sizes = bucket_sizes(dev, run.hist, s.blocks);
    largest = static_cast<uint32_t>(*std::max_element(sizes.begin(), sizes.end()));
    const uint32_t threads = std::max(1u, std::thread::hardware_concurrency());
    // Under a loop cap (lavapipe) the in-bucket sort's nested loops add up to about 900 iterations per key of
    // the largest bucket; only tiny buckets stay inside it.
    bool fits = info.max_loop_iterations == 0 || uint64_t{largest} * 900 < info.max_loop_iterations;
    bool balanced = uint64_t{largest} * 2 * threads <= n;  // every thread gets buckets to sort
    hybrid = fits && (balanced || strategy == SortStrategy::Hybrid);
  }
  if (hybrid) {
    run.scan_and_scatter(keys, keys_alt, values, values ? &values_alt : nullptr);
    Kernel& local_sort = dev.kernel(k64 ? KernelId::radix_local_sort_k64 : KernelId::radix_local_sort_k32);
    Buffer* sorted_values = values ? &values_alt : nullptr;
    if (!on_prefix) {
      sort_buckets(run, keys_alt, keys, sorted_values, values, msd, low, largest, local_sort, 0, MV_RADIX_BUCKETS);
    } else {
      // A range of buckets at a time, each submitted as recorded; while one range sorts, the caller reads the
      // prefix the one before it finished (its own device work then waits behind the running range alone).
      uint32_t first = 0;
      uint64_t end = 0, ready_end = 0;
      Device::StreamMark ready = 0;
      for (uint32_t last : bucket_ranges(sizes, n, ranges)) {
        sort_buckets(run, keys_alt, keys, sorted_values, values, msd, low, largest, local_sort, first, last);
        const Device::StreamMark mark = dev.submit();
        for (; first < last; ++first) end += sizes[first];
        if (ready) {
          dev.wait(ready);
          (*on_prefix)(keys_alt, sorted_values, ready_end);
        }
        ready = mark;
        ready_end = end;
      }
      dev.wait(ready);
      (*on_prefix)(keys_alt, sorted_values, n);
      report.prefixes = true;
    }
    std::swap(keys, keys_alt);  // the buckets were sorted where the global pass left them
    if (values) std::swap(*values, values_alt);
    report.passes = 1 + (msd - low + MV_RADIX_BITS - 1) / MV_RADIX_BITS;
    report.hybrid = true;
    return report;
  }

  Buffer* kin = &keys;
  Buffer* kout = &keys_alt;
  Buffer* vin = values;
  Buffer* vout = values ? &values_alt : nullptr;
  for (uint32_t shift : lsd_shifts(varying)) {
    run.count(*kin, shift);
    run.scan_and_scatter(*kin, *kout, vin, vout);
    std::swap(kin, kout);
    std::swap(vin, vout);
    ++report.passes;
  }
  if (kin != &keys) {  // an odd number of passes: the sorted data sits in the scratch buffers
    std::swap(keys, keys_alt);
    if (values) std::swap(*values, values_alt);
  }
  return report;
}

}  // namespace

SortReport radix_sort(Device& dev, Buffer& keys, Buffer* values, uint64_t n, KeyBits bits, SortStrategy strategy) {
  return sort_on_device(dev, keys, values, n, bits, strategy, nullptr, 1);
}

SortReport radix_sort_packed(Device& dev, Buffer& keys, uint64_t n, uint32_t payload_bits) {
  if (payload_bits % MV_RADIX_BITS != 0 || payload_bits >= 64)
    throw Error("radix_sort_packed: a payload of " + std::to_string(payload_bits) + " bits is not whole digits below the key");
  return sort_on_device(dev, keys, nullptr, n, KeyBits::k64, SortStrategy::Auto, nullptr, 1, payload_bits);
}

Buffer radix_sort_order(Device& dev, Buffer& keys, uint64_t n) {
  std::vector<uint32_t> places(n);
  for (uint64_t i = 0; i < n; ++i) places[i] = static_cast<uint32_t>(i);
  Buffer order = dev.alloc(std::max<uint64_t>(n, 1) * 4, "sort order");
  dev.upload(order, places.data(), n * 4);
  radix_sort(dev, keys, &order, n, KeyBits::k64);
  return order;
}

SortReport radix_sort(Device& dev, Buffer& keys, Buffer* values, uint64_t n, KeyBits bits, SortStrategy strategy,
                      const SortedPrefix& on_prefix, uint32_t ranges) {
  SortReport report = sort_on_device(dev, keys, values, n, bits, strategy, on_prefix ? &on_prefix : nullptr,
                                     std::max(1u, ranges));
  if (on_prefix && !report.prefixes) {  // another path: the whole result at once
    dev.wait(dev.submit());
    on_prefix(keys, values, n);
  }
  return report;
}

namespace {

// Merges consecutive sorted runs of `run` keys (the last may be shorter) pairwise into one sorted sequence.
// Of equal keys the earlier run's go first, so the result is the stable sort of the whole input.
template <class Key>
void merge_runs(std::vector<Key>& keys, std::vector<uint32_t>* values, uint64_t run) {
  const uint64_t n = keys.size();
  std::vector<Key> k(n);
  std::vector<uint32_t> v(values ? n : 0);
  for (uint64_t width = run; width < n; width *= 2) {
    tbb::parallel_for(uint64_t{0}, (n + 2 * width - 1) / (2 * width), [&](uint64_t pair) {
      const uint64_t lo = pair * 2 * width, mid = std::min(lo + width, n), hi = std::min(lo + 2 * width, n);
      for (uint64_t o = lo, a = lo, b = mid; o < hi; ++o) {
        const uint64_t from = b == hi || (a < mid && !(keys[b] < keys[a])) ? a++ : b++;
        k[o] = keys[from];
        if (values) v[o] = (*values)[from];
      }
    });
    keys.swap(k);
    if (values) values->swap(v);
  }
}

template <class Key>
SortReport sort_host(Device& dev, std::vector<Key>& keys, std::vector<uint32_t>* values, SortStrategy strategy,
                     uint64_t chunk) {
  if (values && values->size() != keys.size()) throw Error("radix_sort: keys and values differ in length");
  const uint64_t n = keys.size();
  if (n <= 1) return {};
  const uint64_t run = std::clamp<uint64_t>(chunk, 1, n);
  const KeyBits bits = sizeof(Key) == 8 ? KeyBits::k64 : KeyBits::k32;
  Buffer kb = dev.alloc(run * sizeof(Key), "keys");
  Buffer vb = values ? dev.alloc(run * 4, "values") : Buffer();
  SortReport report;
  report.runs = (n + run - 1) / run;
  for (uint64_t first = 0; first < n; first += run) {
    const uint64_t m = std::min(run, n - first);
    dev.upload(kb, keys.data() + first, m * sizeof(Key));
    if (values) dev.upload(vb, values->data() + first, m * 4);
    SortReport r = radix_sort(dev, kb, values ? &vb : nullptr, m, bits, strategy);
    dev.finish();
    dev.download(kb, keys.data() + first, m * sizeof(Key));
    if (values) dev.download(vb, values->data() + first, m * 4);
    if (m < 2) continue;  // a lone key reports nothing
    report.passes = std::max(report.passes, r.passes);
    report.digits_skipped = first == 0 ? r.digits_skipped : std::min(report.digits_skipped, r.digits_skipped);
    report.hybrid |= r.hybrid;
    report.cooperative |= r.cooperative;
  }
  if (report.runs > 1) merge_runs(keys, values, run);
  return report;
}

// Runs as long as the device holds: per key, the key and its value and a scratch copy of each.
template <class Key>
SortReport sort_host(Device& dev, std::vector<Key>& keys, std::vector<uint32_t>* values, SortStrategy strategy) {
  const uint64_t item = 2 * (sizeof(Key) + (values ? 4 : 0));
  return sort_host(dev, keys, values, strategy,
                   keys.size() > 1 ? detail::device_chunk(dev, "radix_sort", item, sizeof(Key)) : 1);
}

}  // namespace

SortReport radix_sort(Device& dev, std::vector<uint32_t>& keys, std::vector<uint32_t>* values, SortStrategy strategy) {
  return sort_host(dev, keys, values, strategy);
}
SortReport radix_sort(Device& dev, std::vector<uint64_t>& keys, std::vector<uint32_t>* values, SortStrategy strategy) {
  return sort_host(dev, keys, values, strategy);
}

namespace detail {

SortReport radix_sort_chunked(Device& dev, std::vector<uint32_t>& keys, std::vector<uint32_t>* values,
                              SortStrategy strategy, uint64_t chunk) {
  return sort_host(dev, keys, values, strategy, chunk);
}
SortReport radix_sort_chunked(Device& dev, std::vector<uint64_t>& keys, std::vector<uint32_t>* values,
                              SortStrategy strategy, uint64_t chunk) {
  return sort_host(dev, keys, values, strategy, chunk);
}

}  // namespace detail

}  // namespace mv
