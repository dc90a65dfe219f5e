// Host side of the stable radix sort (kernels: kernels/common/radix_sort_body.h).
#include "../kernels/common/radix_sort.h"

#include <algorithm>
#include <thread>
#include <utility>

#include "chunking.h"
#include "launch_shape.h"
#include "megavox/error.h"
#include "megavox/primitives.h"
#include "scan_plan.h"

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

// One sort: the kernels, buffers and shape shared by its passes.
struct SortRun {
  Device& dev;
  BlockShape shape;
  MvRadixParams p;
  Kernel& histogram;
  Kernel& scatter;
  Kernel& local_sort;
  Buffer hist;  // blocks x 256 counts (+1 for the scan total)
  ScanPlan scan;

  // histogram + scan of digit `d` of `keys`: hist then holds each (digit, block)'s first output position.
  void count(const Buffer& keys, uint32_t d) {
    p.shift = 8 * d;
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

// Largest bucket of the counted digit (the counts are read back: one wait).
uint32_t largest_bucket(Device& dev, const Buffer& hist, uint32_t blocks) {
  std::vector<uint32_t> h(size_t{blocks} * MV_RADIX_BUCKETS);
  dev.download(hist, h.data(), h.size() * 4);
  uint32_t largest = 0;
  for (uint32_t d = 0; d < MV_RADIX_BUCKETS; ++d) {
    uint64_t size = 0;
    for (uint32_t b = 0; b < blocks; ++b) size += h[size_t{d} * blocks + b];
    largest = std::max<uint32_t>(largest, static_cast<uint32_t>(size));
  }
  return largest;
}

}  // namespace

SortReport radix_sort(Device& dev, Buffer& keys, Buffer* values, uint64_t n, KeyBits bits, SortStrategy strategy) {
  SortReport report;
  if (n <= 1) return report;
  detail::check_device_items("radix_sort", n);
  const bool k64 = bits == KeyBits::k64;
  const uint64_t key_bytes = k64 ? 8 : 4;
  if (keys.bytes() < n * key_bytes || (values && values->bytes() < n * 4))
    throw Error("radix_sort: buffers too small for " + std::to_string(n) + " keys");

  const DeviceInfo& info = dev.info();
  BlockShape s = block_shape(info, n);
  const std::string sfx = k64 ? "_k64" : "_k32";
  Kernel& or_and = dev.kernel("radix_or_and" + sfx);

  Buffer red = dev.alloc(uint64_t{s.blocks} * 2 * key_bytes, "radix sort key reduction");
  MvRadixParams p{static_cast<uint32_t>(n), s.blocks, s.block_size, 0, values ? 1u : 0u, 0};
  dev.dispatch(or_and, s.groups, s.local_size, {&keys, &red}, p);
  dev.barrier();
  uint64_t varying = k64 ? varying_bits<uint64_t>(dev, red, s.blocks) : varying_bits<uint32_t>(dev, red, s.blocks);

  const uint32_t digits = k64 ? 8 : 4;
  std::vector<uint32_t> vary;  // varying digits, least significant first
  for (uint32_t d = 0; d < digits; ++d) {
    if ((varying >> (8 * d)) & 0xff) vary.push_back(d);
    else ++report.digits_skipped;
  }
  if (vary.empty()) return report;

  SortRun run{dev,
              s,
              p,
              dev.kernel("radix_histogram" + sfx),
              dev.kernel("radix_scatter" + sfx),
              dev.kernel("radix_local_sort" + sfx),
              dev.alloc((uint64_t{s.blocks} * MV_RADIX_BUCKETS + 1) * 4, "radix sort histograms"),
              plan_scan(dev, s.blocks * MV_RADIX_BUCKETS)};
  Buffer keys_alt = dev.alloc(n * key_bytes, "radix sort scratch keys");
  Buffer values_alt = values ? dev.alloc(n * 4, "radix sort scratch values") : Buffer();

  bool hybrid = strategy == SortStrategy::Hybrid ||
                (strategy == SortStrategy::Auto && !info.massively_parallel && vary.size() >= 2);
  if (hybrid) {
    run.count(keys, vary.back());
    uint32_t largest = largest_bucket(dev, run.hist, s.blocks);
    const uint32_t threads = std::max(1u, std::thread::hardware_concurrency());
    // Under a loop cap (lavapipe) the in-bucket sort's nested loops add up to about 900 iterations per key of
    // the largest bucket; only tiny buckets stay inside it.
    bool fits = info.max_loop_iterations == 0 || uint64_t{largest} * 900 < info.max_loop_iterations;
    bool balanced = uint64_t{largest} * 2 * threads <= n;  // every thread gets buckets to sort
    hybrid = fits && (balanced || strategy == SortStrategy::Hybrid);
  }
  if (hybrid) {
    run.scan_and_scatter(keys, keys_alt, values, values ? &values_alt : nullptr);
    for (size_t i = 0; i + 1 < vary.size(); ++i) run.p.local_digits |= 1u << vary[i];
    uint32_t local = s.local_size;
    dev.dispatch(run.local_sort, (MV_RADIX_BUCKETS + local - 1) / local, local,
                 {&keys, &keys_alt, values ? values : &keys, values ? &values_alt : &keys_alt, &run.hist}, run.p);
    dev.barrier();
    report.passes = static_cast<uint32_t>(vary.size());
    report.hybrid = true;
    return report;
  }

  Buffer* kin = &keys;
  Buffer* kout = &keys_alt;
  Buffer* vin = values;
  Buffer* vout = values ? &values_alt : nullptr;
  for (uint32_t d : vary) {
    run.count(*kin, d);
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

namespace {

template <class Key>
SortReport sort_host(Device& dev, std::vector<Key>& keys, std::vector<uint32_t>* values, SortStrategy strategy) {
  if (values && values->size() != keys.size()) throw Error("radix_sort: keys and values differ in length");
  const uint64_t n = keys.size();
  if (n <= 1) return {};
  detail::check_device_items("radix_sort", n);
  Buffer kb = dev.alloc(n * sizeof(Key), "keys");
  dev.upload(kb, keys.data(), n * sizeof(Key));
  Buffer vb;
  if (values) {
    vb = dev.alloc(n * 4, "values");
    dev.upload(vb, values->data(), n * 4);
  }
  SortReport r = radix_sort(dev, kb, values ? &vb : nullptr, n, sizeof(Key) == 8 ? KeyBits::k64 : KeyBits::k32,
                            strategy);
  dev.finish();
  dev.download(kb, keys.data(), n * sizeof(Key));
  if (values) dev.download(vb, values->data(), n * 4);
  return r;
}

}  // namespace

SortReport radix_sort(Device& dev, std::vector<uint32_t>& keys, std::vector<uint32_t>* values, SortStrategy strategy) {
  return sort_host(dev, keys, values, strategy);
}
SortReport radix_sort(Device& dev, std::vector<uint64_t>& keys, std::vector<uint32_t>* values, SortStrategy strategy) {
  return sort_host(dev, keys, values, strategy);
}

}  // namespace mv
