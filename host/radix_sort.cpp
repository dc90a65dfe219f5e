// Host side of the stable LSD radix sort (kernels: kernels/common/radix_sort_body.h).
#include "../kernels/common/radix_sort.h"

#include <utility>

#include "launch_shape.h"
#include "scan_plan.h"
#include "megavox/error.h"
#include "megavox/primitives.h"

namespace mv {

namespace {

template <class Key>
Key varying_bits(Device& dev, const Buffer& red, uint32_t blocks) {
  std::vector<Key> r(size_t{blocks} * 2);
  dev.download(red, r.data(), r.size() * sizeof(Key));
  Key acc_or = 0, acc_and = ~Key{0};
  for (uint32_t b = 0; b < blocks; ++b) {
    acc_or |= r[2 * b];
    acc_and &= r[2 * b + 1];
  }
  return acc_or ^ acc_and;  // a bit is constant over all keys iff OR and AND agree on it
}

}  // namespace

SortReport radix_sort(Device& dev, Buffer& keys, Buffer* values, uint32_t n, KeyBits bits) {
  SortReport report;
  if (n <= 1) return report;
  const bool k64 = bits == KeyBits::k64;
  const uint64_t key_bytes = k64 ? 8 : 4;
  if (keys.bytes() < n * key_bytes || (values && values->bytes() < uint64_t{n} * 4))
    throw Error("radix_sort: buffers too small for " + std::to_string(n) + " keys");

  BlockShape s = block_shape(dev.info(), n);
  MvRadixParams p{n, s.blocks, s.block_size, 0, values ? 1u : 0u, 0};
  const char* sfx = k64 ? "_k64" : "_k32";
  Kernel& or_and = dev.kernel(std::string("radix_or_and") + sfx);
  Kernel& histogram = dev.kernel(std::string("radix_histogram") + sfx);
  Kernel& scatter = dev.kernel(std::string("radix_scatter") + sfx);

  Buffer red = dev.alloc(uint64_t{s.blocks} * 2 * key_bytes, "radix sort key reduction");
  dev.dispatch(or_and, s.groups, s.local_size, {&keys, &red}, p);
  dev.barrier();
  uint64_t varying = k64 ? varying_bits<uint64_t>(dev, red, s.blocks) : varying_bits<uint32_t>(dev, red, s.blocks);

  const uint32_t digits = k64 ? 8 : 4;
  for (uint32_t d = 0; d < digits; ++d)
    if (((varying >> (8 * d)) & 0xff) == 0) ++report.digits_skipped;
  if (report.digits_skipped == digits) return report;

  Buffer hist = dev.alloc((uint64_t{s.blocks} * MV_RADIX_BUCKETS + 1) * 4, "radix sort histograms");
  Buffer keys_alt = dev.alloc(uint64_t{n} * key_bytes, "radix sort scratch keys");
  Buffer values_alt = values ? dev.alloc(uint64_t{n} * 4, "radix sort scratch values") : Buffer();
  Buffer* kin = &keys;
  Buffer* kout = &keys_alt;
  Buffer* vin = values;
  Buffer* vout = values ? &values_alt : nullptr;
  ScanPlan scan = plan_scan(dev, s.blocks * MV_RADIX_BUCKETS);

  for (uint32_t d = 0; d < digits; ++d) {
    if (((varying >> (8 * d)) & 0xff) == 0) continue;
    p.shift = 8 * d;
    dev.dispatch(histogram, s.groups, s.local_size, {kin, &hist}, p);
    dev.barrier();
    record_scan(dev, scan, hist, hist);
    dev.dispatch(scatter, s.groups, s.local_size, {kin, kout, vin ? vin : kin, vout ? vout : kout, &hist}, p);
    dev.barrier();
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
SortReport sort_host(Device& dev, std::vector<Key>& keys, std::vector<uint32_t>* values) {
  if (values && values->size() != keys.size()) throw Error("radix_sort: keys and values differ in length");
  if (keys.size() > UINT32_MAX) throw Error("radix_sort: more than 2^32-1 keys");
  auto n = static_cast<uint32_t>(keys.size());
  if (n <= 1) return {};
  Buffer kb = dev.alloc(uint64_t{n} * sizeof(Key), "keys");
  dev.upload(kb, keys.data(), uint64_t{n} * sizeof(Key));
  Buffer vb;
  if (values) {
    vb = dev.alloc(uint64_t{n} * 4, "values");
    dev.upload(vb, values->data(), uint64_t{n} * 4);
  }
  SortReport r = radix_sort(dev, kb, values ? &vb : nullptr, n, sizeof(Key) == 8 ? KeyBits::k64 : KeyBits::k32);
  dev.finish();
  dev.download(kb, keys.data(), uint64_t{n} * sizeof(Key));
  if (values) dev.download(vb, values->data(), uint64_t{n} * 4);
  return r;
}

}  // namespace

SortReport radix_sort(Device& dev, std::vector<uint32_t>& keys, std::vector<uint32_t>* values) {
  return sort_host(dev, keys, values);
}
SortReport radix_sort(Device& dev, std::vector<uint64_t>& keys, std::vector<uint32_t>* values) {
  return sort_host(dev, keys, values);
}

}  // namespace mv
