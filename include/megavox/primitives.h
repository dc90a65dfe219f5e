// megavox — data-parallel primitives on a Device: Morton encoding, exclusive scan, stable radix sort.
// These are the shared pieces later stages (DAG reduction, point hierarchies, the page cache's LRU) build on.
// Every function records work on the device's stream and returns without waiting, except where noted.
#pragma once
#include <cstdint>
#include <vector>

#include "megavox/device.h"

namespace mv {

enum class KeyBits { k32 = 32, k64 = 64 };

// keys[i] = Morton code of (xyz[3i], xyz[3i+1], xyz[3i+2]); x in the lowest bit. 64-bit keys interleave
// 3 x 21 bits, 32-bit keys 3 x 10 bits; higher coordinate bits are ignored.
void morton_encode(Device& dev, const Buffer& xyz, Buffer& keys, uint32_t n, KeyBits bits);

// dst[i] = src[0] + ... + src[i-1] for i < n, and dst[n] = the total (dst holds n + 1 values).
// src and dst may be the same buffer.
void exclusive_scan(Device& dev, const Buffer& src, Buffer& dst, uint32_t n);

struct SortReport {
  uint32_t passes = 0;          // 8-bit digit passes run
  uint32_t digits_skipped = 0;  // digits constant over all keys
};

// Stable LSD radix sort of n keys (32- or 64-bit), with 32-bit values moved along when `values` is not null.
// Waits once, to learn which digits vary. On return `keys` (and `*values`) hold the sorted data; the Buffer
// objects may have been swapped with scratch buffers of the same size, so keep using these objects.
SortReport radix_sort(Device& dev, Buffer& keys, Buffer* values, uint32_t n, KeyBits bits);

// Host convenience: upload, sort, download (keys-only when values is null). Waits.
SortReport radix_sort(Device& dev, std::vector<uint32_t>& keys, std::vector<uint32_t>* values);
SortReport radix_sort(Device& dev, std::vector<uint64_t>& keys, std::vector<uint32_t>* values);

}  // namespace mv
