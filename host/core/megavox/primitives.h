// megavox — data-parallel primitives on a Device: Morton encoding, exclusive scan, unique, stable radix sort.
// These are the shared pieces later stages (DAG reduction, point hierarchies, the page cache's LRU) build on.
// Every function records work on the device's stream and returns without waiting, except where noted.
//
// Counts are 64-bit. A call on device buffers covers at most kMaxDeviceItems items (the kernels index with 32
// bits, which Vulkan reads as signed) and what its buffers hold, so the device's memory is what bounds it in
// practice (PoCL: 1 GiB per buffer); more throws mv::Error. Larger inputs, such as a point cloud past 4 G
// points, take the overloads on host arrays: host-driven loops over device-sized chunks that carry 64-bit state
// (a running total, an output position, the key at the seam) from one chunk to the next.
#pragma once
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include "megavox/device.h"

namespace mv {

inline constexpr uint64_t kMaxDeviceItems = (uint64_t{1} << 31) - 1;

enum class KeyBits { k32 = 32, k64 = 64 };

// Whether `dev` computes in host memory (a CPU device: PoCL, lavapipe). There a step whose kernel would be the
// host's own loop plus copies up and down stays on the host (the points' gathers, the quantizer's nearest
// centres); its kernel is tested on every device all the same.
bool computes_in_host_memory(Device& dev);

// keys[i] = Morton code of (xyz[3i], xyz[3i+1], xyz[3i+2]); x in the lowest bit. 64-bit keys interleave
// 3 x 21 bits, 32-bit keys 3 x 10 bits; higher coordinate bits are ignored.
void morton_encode(Device& dev, const Buffer& xyz, Buffer& keys, uint64_t n, KeyBits bits);

// dst[i] = src[0] + ... + src[i-1] for i < n, and dst[n] = the total (dst holds n + 1 values), as 32-bit
// sums: mod 2^32 once a prefix passes 2^32. src and dst may be the same buffer.
void exclusive_scan(Device& dev, const Buffer& src, Buffer& dst, uint64_t n);

// The same into exact 64-bit sums from `start`: dst holds n + 1 uint64_t values, dst[i] = start + src[0] + ...
// + src[i-1]. src and dst must be different buffers.
void exclusive_scan64(Device& dev, const Buffer& src, Buffer& dst, uint64_t n, uint64_t start = 0);

// Host arrays of any length: out[i] = in[0] + ... + in[i-1] in 64 bits, out[n] = the total, which is returned
// (out holds in.size() + 1 values). Chunks that fit the device are scanned there with exclusive_scan64, each
// from the running total of the chunks before it. Waits.
uint64_t exclusive_scan(Device& dev, std::span<const uint32_t> in, std::span<uint64_t> out);

// Removes repeats from n sorted 64-bit keys: `out` (another buffer of n keys) receives the distinct keys in
// order. Returns how many there are (waits once, to read the count). Output positions are 32-bit on the device,
// within the one call.
uint64_t unique_sorted(Device& dev, const Buffer& keys, Buffer& out, uint64_t n);

// Host arrays of any length: the distinct keys of sorted `keys`, in order, to the front of `out` (at least as
// long as keys; it may be keys' own storage). Returns how many. Chunks that fit the device are made unique
// there; a chunk's first key equal to the last key kept (a run across the seam, or a chunk all of one key) is
// dropped on the host, and output positions count in 64 bits. Waits.
uint64_t unique_sorted(Device& dev, std::span<const uint64_t> keys, std::span<uint64_t> out);

// dst record i = src record index[i] for n records of `record_bytes` bytes each (index: n 32-bit record numbers;
// dst: n * record_bytes bytes, rounded up to whole 32-bit words, the padding of the last word zero). One
// work-item per output word: any record size packs without atomics. Queues the dispatch (no wait).
// A source larger than one binding goes in slices: `src` then holds records [slice.first, slice.first +
// slice.count) of the whole source, and every pass but the first merges (keeps what earlier slices wrote).
struct GatherSlice {
  uint32_t first = 0;
  uint32_t count = UINT32_MAX;
  bool merge = false;
};
void gather_records(Device& dev, const Buffer& src, const Buffer& index, Buffer& dst, uint64_t n, uint32_t record_bytes,
                    const GatherSlice& slice = {});

struct SortReport {
  uint32_t passes = 0;          // 8-bit digits sorted on (global passes, or global + in-bucket with hybrid)
  uint32_t digits_skipped = 0;  // digits constant over all keys
  bool hybrid = false;          // one global pass on the top digit, then each bucket sorted in cache
  bool cooperative = false;     // the work-group-cooperative LSD passes (tiles ranked in shared memory)
  uint64_t runs = 1;            // host vectors: runs sorted on the device and merged on the host; with more than
                                // one, the most passes, the fewest skipped digits and whether any run was hybrid
  bool prefixes = false;        // radix_sort with a SortedPrefix: prefixes were handed over while it sorted
};

// Lsd: one global pass per varying digit, each work-item walking one block of keys (any device). Hybrid: one
// global pass on the most significant varying digit, then each of its 256 buckets sorted in cache (fast on CPUs
// when the keys spread over the buckets). Cooperative: the LSD passes with work-groups ranking tiles of keys in
// shared memory (for GPUs; it runs on any device with the work-group size and shared memory it needs, see
// cooperative_sort_fits, and throws mv::Error elsewhere). Auto: Cooperative where prefers_cooperative_sort says so, else Hybrid on
// CPU devices when the buckets are balanced, else Lsd. Hybrid falls back to Lsd where a bucket would be too
// large for the device (a loop cap). Same output, byte for byte, whichever runs.
enum class SortStrategy { Auto, Lsd, Hybrid, Cooperative };

// Whether the device can run the cooperative sort (work-groups of 128 items, 23.5 KiB of shared memory), and
// whether Auto picks it there: on GPUs (DeviceInfo::massively_parallel).
bool cooperative_sort_fits(const DeviceInfo& info);
bool prefers_cooperative_sort(const DeviceInfo& info);

// Stable LSD radix sort of n keys (32- or 64-bit), with 32-bit values moved along when `values` is not null.
// Waits once, to learn which digits vary. On return `keys` (and `*values`) hold the sorted data; the Buffer
// objects may have been swapped with scratch buffers of the same size, so keep using these objects.
// n is bounded by device memory: keys, values and a scratch copy of each sit on the device at once, and when
// the scratch does not fit what is left of the budget this throws mv::DeviceMemoryError naming what it needs.
SortReport radix_sort(Device& dev, Buffer& keys, Buffer* values, uint64_t n, KeyBits bits,
                      SortStrategy strategy = SortStrategy::Auto);

// The same sort of n 64-bit keys on their bits from `payload_bits` up (whole 8-bit digits): the bits below ride
// along, so equal keys end up together, their payloads in an order that depends on the path the sort takes (for
// what sums them). A payload packed beside the key (a point's colour beside its cell's code) costs no pass and no
// second column.
SortReport radix_sort_packed(Device& dev, Buffer& keys, uint64_t n, uint32_t payload_bits);

// The same sort of n 64-bit keys, their places moved along: returns the permutation (n 32-bit values; value i =
// the place sorted key i had), by which other columns follow the keys (gather_records).
Buffer radix_sort_order(Device& dev, Buffer& keys, uint64_t n);

// Sorted prefixes while the sort goes on: [0, end) of `keys` (and `values`) is sorted and final, readable on the
// host (Device::host_view; a download waits for the rest too), and `end` grows from call to call up to n. Work
// the callee records on the device runs after the part of the sort that is running then.
using SortedPrefix = std::function<void(const Buffer& keys, const Buffer* values, uint64_t end)>;
// The same sort, handing over sorted prefixes as it goes (each such Buffer is one of the two this call ends with
// in `keys` / `values`). Where the hybrid runs, its in-bucket stage is cut into up to `ranges` ranges of top-digit
// buckets of about equal size, each submitted when recorded: while one range sorts, `on_prefix` gets the prefix
// the ones before it finished (SortReport::prefixes). Other paths call it once, with n, when the sort is done.
// Waits for the device. An empty `on_prefix` makes it the sort above.
SortReport radix_sort(Device& dev, Buffer& keys, Buffer* values, uint64_t n, KeyBits bits, SortStrategy strategy,
                      const SortedPrefix& on_prefix, uint32_t ranges = 8);

// Host convenience: upload, sort, download (keys-only when values is null). Waits. Any length: keys the device
// cannot hold at once are sorted there in runs it can, merged on the host (which takes a second copy of keys
// and values in host memory), stably: equal keys keep their input order across runs. Values stay 32-bit
// payloads, so past 2^32 keys they cannot index every key: such callers sort chunk-relative indices, or keys
// that carry their own.
SortReport radix_sort(Device& dev, std::vector<uint32_t>& keys, std::vector<uint32_t>* values,
                      SortStrategy strategy = SortStrategy::Auto);
SortReport radix_sort(Device& dev, std::vector<uint64_t>& keys, std::vector<uint32_t>* values,
                      SortStrategy strategy = SortStrategy::Auto);

}  // namespace mv
