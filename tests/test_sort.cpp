// Radix sort on every device vs std::stable_sort, byte for byte, keys-only and (key, value) pairs; host vectors
// in runs merged on the host.
#include <algorithm>
#include <cstring>
#include <numeric>
#include <utility>

#include "primitives/chunking.h"
#include "common/radix_sort.h"
#include "reference.h"
#include "megavox/primitives.h"
#include "test_support.h"

namespace mv::test {
namespace {

// Every case runs with each strategy, whatever the device would pick by itself: the plain global LSD passes
// (a block per work-item), the hybrid (global top digit, then buckets sorted in cache) and the cooperative LSD
// passes (work-groups ranking tiles in shared memory), so each variant is tested on both backends.
class SortTest : public ::testing::TestWithParam<DeviceInfo> {
 protected:
  Device& dev() { return shared_device(GetParam()); }

  template <class Key>
  void check(const std::vector<Key>& keys) {
    for (SortStrategy s : {SortStrategy::Lsd, SortStrategy::Hybrid, SortStrategy::Cooperative, SortStrategy::Auto}) {
      strategy_ = s;
      check_one(keys);
      if (HasFatalFailure()) return;
    }
  }

  // Sorts `keys` on the device twice (keys only; pairs with values = index) and compares with the reference.
  template <class Key>
  void check_one(const std::vector<Key>& keys) {
    SCOPED_TRACE(strategy_ == SortStrategy::Lsd           ? "Lsd"
                 : strategy_ == SortStrategy::Hybrid      ? "Hybrid"
                 : strategy_ == SortStrategy::Cooperative ? "Cooperative"
                                                          : "Auto");
    std::vector<Key> expect_keys = keys;
    ref::stable_sort<Key>(expect_keys, nullptr);
    std::vector<Key> got = keys;
    radix_sort(dev(), got, nullptr, strategy_);
    ASSERT_TRUE(got == expect_keys) << "keys-only sort differs, n = " << keys.size();

    std::vector<uint32_t> values(keys.size()), expect_values(keys.size());
    for (uint32_t i = 0; i < values.size(); ++i) values[i] = expect_values[i] = i;
    expect_keys = keys;
    ref::stable_sort<Key>(expect_keys, &expect_values);
    got = keys;
    radix_sort(dev(), got, &values, strategy_);
    ASSERT_TRUE(got == expect_keys) << "pair sort keys differ, n = " << keys.size();
    ASSERT_TRUE(values == expect_values) << "pair sort values differ (stability), n = " << keys.size();
  }

  template <class Key>
  std::vector<Key> random(size_t n, uint64_t seed) {
    if constexpr (sizeof(Key) == 8) return random_u64(n, seed);
    else return random_u32(n, seed);
  }

  template <class Key>
  void check_all_shapes() {
    // Around the cooperative variant's tile (1024) and block (8192) and the block variant's 4096 keys per block.
    for (size_t n : {size_t{0}, size_t{1}, size_t{2}, size_t{255}, size_t{256}, size_t{257}, size_t{1023}, size_t{1025},
                     size_t{4097}, size_t{8191}, size_t{8193}, size_t{3 * 8192 + 5}})
      check<Key>(random<Key>(n, 7 + n));
    // Many blocks and top-digit buckets of ~1000 keys; ArrayLargerThan128MiB covers the large sizes.
    const size_t big = (size_t{1} << 18) + 3;
    auto r = random<Key>(big, 42);
    check<Key>(r);
    std::vector<Key> equal(big, Key(0x5a5a5a5a));
    check<Key>(equal);
    std::vector<Key> sorted = r;
    std::sort(sorted.begin(), sorted.end());
    check<Key>(sorted);
    std::vector<Key> reversed(sorted.rbegin(), sorted.rend());
    check<Key>(reversed);
    std::vector<Key> low = r;  // only the low 4 bits vary: many ties, all but one digit skipped
    for (auto& k : low) k &= Key(0xf);
    check<Key>(low);
    std::vector<Key> high = r;  // only the top byte varies
    for (auto& k : high) k = (k >> (sizeof(Key) * 8 - 8)) << (sizeof(Key) * 8 - 8);
    check<Key>(high);
    std::vector<Key> two = r;  // two varying digits far apart: one global pass, one in-bucket pass
    for (auto& k : two) k &= (Key(0xff) << (sizeof(Key) * 8 - 16)) | Key(0xff);
    check<Key>(two);
    std::vector<Key> skewed = r;  // most keys in one top-digit bucket: Auto must stay correct
    for (size_t i = 0; i < skewed.size(); ++i)
      if (i % 10) skewed[i] &= ~(Key(0xff) << (sizeof(Key) * 8 - 8));
    check<Key>(skewed);
  }

  SortStrategy strategy_ = SortStrategy::Auto;
};

TEST_P(SortTest, Keys32AllShapes) { check_all_shapes<uint32_t>(); }

// Small inputs with many ties and digits that are not byte-aligned: bits 5..20 vary, so the digits start at
// bit 5 and the last one reaches past the varying bits.
TEST_P(SortTest, UnalignedDigitsAndTies) {
  std::vector<uint64_t> keys = random_u64(20000, 5);
  for (auto& k : keys) k = (k & 0x1fffe0ull & ~0x3f00ull) | 0x700000000ull;
  check<uint64_t>(keys);
  std::vector<uint32_t> keys32 = random_u32(20000, 6);
  for (auto& k : keys32) k = (k & 0x00ff0f00u) | 0x80000000u;
  check<uint32_t>(keys32);
}

TEST_P(SortTest, CooperativeRunsWhenForcedAndAutoFollowsTheDevice) {
  std::vector<uint64_t> keys = random_u64(50000, 21), expect = keys;
  std::vector<uint32_t> values(keys.size()), expect_values;
  std::iota(values.begin(), values.end(), 0u);
  expect_values = values;
  ref::stable_sort<uint64_t>(expect, &expect_values);
  std::vector<uint64_t> got = keys;
  std::vector<uint32_t> got_values = values;
  SortReport r = radix_sort(dev(), got, &got_values, SortStrategy::Cooperative);
  EXPECT_TRUE(r.cooperative);
  EXPECT_FALSE(r.hybrid);
  EXPECT_EQ(r.passes, 8u);
  EXPECT_TRUE(got == expect);
  EXPECT_TRUE(got_values == expect_values);
  got = keys;
  r = radix_sort(dev(), got, nullptr);
  EXPECT_EQ(r.cooperative, prefers_cooperative_sort(GetParam()));
  EXPECT_EQ(prefers_cooperative_sort(GetParam()), GetParam().massively_parallel);
}
TEST_P(SortTest, Keys64AllShapes) { check_all_shapes<uint64_t>(); }

TEST_P(SortTest, SkipsConstantDigits) {
  std::vector<uint64_t> keys = random_u64(10000, 3);
  for (auto& k : keys) k = (k & 0xff00) | 0x1100000000ull;  // digit 1 varies; digits 0, 2..7 constant
  std::vector<uint64_t> expect = keys;
  std::sort(expect.begin(), expect.end());
  SortReport r = radix_sort(dev(), keys, nullptr, SortStrategy::Lsd);
  EXPECT_FALSE(r.hybrid);
  EXPECT_EQ(r.passes, 1u);
  EXPECT_EQ(r.digits_skipped, 7u);
  EXPECT_TRUE(keys == expect);
}

// Arrays over lavapipe's 128 MiB binding limit: kernels address them through buffer device addresses.
TEST_P(SortTest, ArrayLargerThan128MiB) {
  const size_t n = (size_t{17} << 20) + 5;  // 136 MiB of 64-bit keys
  std::vector<uint64_t> keys = random_u64(n, 99);
  std::vector<uint32_t> values(n);
  for (uint32_t i = 0; i < n; ++i) values[i] = i;
  std::vector<uint64_t> expect_keys = keys;
  std::vector<uint32_t> expect_values = values;
  ref::stable_sort<uint64_t>(expect_keys, &expect_values);
  radix_sort(dev(), keys, &values);  // Auto: the strategy the benchmark uses on this device
  ASSERT_TRUE(keys == expect_keys);
  ASSERT_TRUE(values == expect_values);
}

TEST_P(SortTest, HybridRunsWhereBucketsFit) {
  // Buckets of ~12 keys fit every device, lavapipe's loop cap included, so the hybrid kernels run everywhere.
  std::vector<uint64_t> keys = random_u64(3000, 8);
  std::vector<uint32_t> values(keys.size());
  for (uint32_t i = 0; i < values.size(); ++i) values[i] = i;
  std::vector<uint64_t> expect = keys;
  std::vector<uint32_t> expect_values = values;
  ref::stable_sort<uint64_t>(expect, &expect_values);
  SortReport r = radix_sort(dev(), keys, &values, SortStrategy::Hybrid);
  EXPECT_TRUE(r.hybrid);
  EXPECT_TRUE(values == expect_values);
  EXPECT_EQ(r.passes, 8u);
  EXPECT_TRUE(keys == expect);
}

// The hybrid hands over sorted prefixes while it sorts: each is the start of the final sorted data (read in place
// where the device has host views, so without waiting for the ranges still sorting), they grow to n, and work the
// callee records in between runs. Other strategies hand over the whole result once.
TEST_P(SortTest, SortedPrefixesAreFinalAsTheyArrive) {
  Device& d = dev();
  // buckets of ~12 keys under lavapipe's loop cap, as above
  const uint64_t n = d.info().max_loop_iterations ? 3000 : 200000;
  const std::vector<uint64_t> keys = random_u64(n, 21);
  std::vector<uint32_t> index(n);
  for (uint32_t i = 0; i < n; ++i) index[i] = i;
  std::vector<uint64_t> expect = keys;
  std::vector<uint32_t> expect_values = index;
  ref::stable_sort<uint64_t>(expect, &expect_values);
  for (SortStrategy s : {SortStrategy::Hybrid, SortStrategy::Lsd}) {
    SCOPED_TRACE(s == SortStrategy::Hybrid ? "Hybrid" : "Lsd");
    Buffer kb = d.alloc(n * 8, "keys"), vb = d.alloc(n * 4, "values"), side = d.alloc(64, "callee's work");
    d.upload(kb, keys.data(), n * 8);
    d.upload(vb, index.data(), n * 4);
    std::vector<uint64_t> ends;
    auto on_prefix = [&](const Buffer& k, const Buffer* v, uint64_t end) {
      ASSERT_NE(v, nullptr);
      ASSERT_TRUE(ends.empty() || end >= ends.back());
      ends.push_back(end);
      std::vector<uint64_t> got(end);
      std::vector<uint32_t> got_values(end);
      if (const void* view = d.host_view(k)) std::memcpy(got.data(), view, end * 8);
      else d.download(k, got.data(), end * 8);
      if (const void* view = d.host_view(*v)) std::memcpy(got_values.data(), view, end * 4);
      else d.download(*v, got_values.data(), end * 4);
      ASSERT_TRUE(std::equal(got.begin(), got.end(), expect.begin())) << "prefix of " << end;
      ASSERT_TRUE(std::equal(got_values.begin(), got_values.end(), expect_values.begin())) << "prefix of " << end;
      uint32_t word = 0;
      d.fill(side, static_cast<uint32_t>(ends.size()), 64);
      d.download(side, &word, 4);
      EXPECT_EQ(word, ends.size());
    };
    const SortReport r = radix_sort(d, kb, &vb, n, KeyBits::k64, s, on_prefix, 5);
    EXPECT_EQ(r.prefixes, r.hybrid);
    EXPECT_EQ(r.hybrid, s == SortStrategy::Hybrid);
    ASSERT_FALSE(ends.empty());
    EXPECT_EQ(ends.back(), n);
    EXPECT_EQ(ends.size(), r.hybrid ? 5u : 1u);
    std::vector<uint64_t> got(n);
    std::vector<uint32_t> got_values(n);
    d.download(kb, got.data(), n * 8);
    d.download(vb, got_values.data(), n * 4);
    EXPECT_TRUE(got == expect);
    EXPECT_TRUE(got_values == expect_values);
  }
}

// Host vectors through the chunked path with small runs: runs of one key, of a few, one run longer than the
// input. Equal keys spread over several runs keep their input order (values = input index).
TEST_P(SortTest, HostVectorsInRunsMergeStably) {
  for (uint64_t run : {1u, 2u, 3u, 7u, 1000u, 5000u}) {
    const size_t n = run <= 7 ? 30 * run : 3001;  // about 30 runs or more (a device sort each)
    std::vector<uint64_t> r = random_u64(n, run);
    std::vector<uint64_t> ties = r, equal(n, 42), reversed(n);
    for (auto& k : ties) k &= 0xf00000000000000full;
    std::iota(reversed.rbegin(), reversed.rend(), uint64_t{1} << 40);
    for (const auto* shape : {&r, &ties, &equal, &reversed}) {
      SCOPED_TRACE("run " + std::to_string(run));
      std::vector<uint64_t> keys = *shape, expect_keys = *shape;
      std::vector<uint32_t> values(n), expect_values(n);
      std::iota(values.begin(), values.end(), 0u);
      std::iota(expect_values.begin(), expect_values.end(), 0u);
      ref::stable_sort<uint64_t>(expect_keys, &expect_values);
      SortReport rep = detail::radix_sort_chunked(dev(), keys, &values, SortStrategy::Auto, run);
      EXPECT_EQ(rep.runs, (n + run - 1) / run);
      ASSERT_TRUE(keys == expect_keys);
      ASSERT_TRUE(values == expect_values);
    }
    std::vector<uint32_t> keys32 = random_u32(n, run), expect32 = keys32;  // keys only, 32-bit
    for (auto& k : keys32) k &= 0xff0000ffu;
    expect32 = keys32;
    ref::stable_sort<uint32_t>(expect32, nullptr);
    detail::radix_sort_chunked(dev(), keys32, nullptr, SortStrategy::Auto, run);
    ASSERT_TRUE(keys32 == expect32) << "run " << run;
  }
}

// A sort of device buffers whose scratch does not fit what the budget has left names the memory it needs; the
// host overload on the same device sorts those keys in runs that fit and merges them.
TEST_P(SortTest, OverTheBudgetNamesTheNeedOrRunsInPieces) {
  auto small = Device::open({GetParam().selector(), 8u << 20, false});
  const size_t n = size_t{640} << 10;  // 5 MiB of 64-bit keys: their scratch copy is more than the 3 MiB left
  std::vector<uint64_t> keys = random_u64(n, 12);
  {
    Buffer kb = small->alloc(n * 8, "keys");
    small->upload(kb, keys.data(), n * 8);
    std::string msg = error_message([&] { radix_sort(*small, kb, nullptr, n, KeyBits::k64); });
    EXPECT_NE(msg.find("radix_sort: 655360 keys need 5."), std::string::npos) << msg;
    EXPECT_NE(msg.find("budget 8.0 MiB"), std::string::npos) << msg;
  }
  std::vector<uint32_t> values(n), expect_values(n);
  std::iota(values.begin(), values.end(), 0u);
  std::iota(expect_values.begin(), expect_values.end(), 0u);
  std::vector<uint64_t> expect_keys = keys;
  ref::stable_sort<uint64_t>(expect_keys, &expect_values);
  SortReport rep = radix_sort(*small, keys, &values);
  EXPECT_GT(rep.runs, 1u);
  EXPECT_TRUE(keys == expect_keys);
  EXPECT_TRUE(values == expect_values);
}

TEST_P(SortTest, OneDeviceCallIsCappedAtMaxDeviceItems) {
  Buffer keys = dev().alloc(8, "keys");
  std::string msg = error_message([&] { radix_sort(dev(), keys, nullptr, kMaxDeviceItems + 1, KeyBits::k64); });
  EXPECT_NE(msg.find(std::to_string(kMaxDeviceItems)), std::string::npos) << msg;
}

// The streaming scatter, dispatched directly on every device (the sort picks it only where loops are not capped):
// one pass over blocks of any length must equal the stable sort by the pass's digit, with and without values,
// for random keys, keys sharing one digit, a few digits (long runs that fill whole lines) and short blocks.
template <class Key>
void check_streaming_scatter(Device& d) {
  const bool k64 = sizeof(Key) == 8;
  Kernel& k = d.kernel(k64 ? KernelId::radix_scatter_stream_k64 : KernelId::radix_scatter_stream_k32);
  const uint32_t local = d.info().preferred_work_group_size;
  for (uint32_t n : {1u, 15u, 16u, 17u, 1000u, 20011u})
    for (uint32_t shape = 0; shape < 3; ++shape)
      for (uint32_t shift : {0u, 5u, uint32_t(sizeof(Key) * 8 - 8)}) {
        std::vector<Key> keys(n);
        if constexpr (sizeof(Key) == 8) keys = random_u64(n, n + shift);
        else keys = random_u32(n, n + shift);
        if (shape == 1) for (auto& x : keys) x |= Key(0xff) << shift;                  // every key in digit 255
        if (shape == 2) for (auto& x : keys) x &= ~(Key(0xfc) << shift);               // digits 0..3 only
        const uint32_t blocks = std::min<uint32_t>(n, 7), block_size = (n + blocks - 1) / blocks;
        auto digit = [&](Key x) { return uint32_t(x >> shift) & 0xffu; };
        std::vector<uint32_t> offsets(256 * blocks + 2, 0);
        for (uint32_t i = 0; i < n; ++i) offsets[digit(keys[i]) * blocks + i / block_size] += 1;
        for (uint32_t i = 0, acc = 0; i < 256 * blocks; ++i) acc += std::exchange(offsets[i], acc);
        std::vector<Key> expect = keys;
        std::vector<uint32_t> values(n), expect_values(n);
        std::iota(values.begin(), values.end(), 0u);
        std::iota(expect_values.begin(), expect_values.end(), 0u);
        std::stable_sort(expect_values.begin(), expect_values.end(),
                         [&](uint32_t a, uint32_t b) { return digit(keys[a]) < digit(keys[b]); });
        for (uint32_t i = 0; i < n; ++i) expect[i] = keys[expect_values[i]];
        for (uint32_t has_values : {0u, 1u}) {
          SCOPED_TRACE("n " + std::to_string(n) + ", shape " + std::to_string(shape) + ", shift " +
                       std::to_string(shift) + ", values " + std::to_string(has_values));
          Buffer kin = d.alloc(n * sizeof(Key), "keys"), kout = d.alloc(n * sizeof(Key), "sorted keys");
          Buffer vin = d.alloc(n * 4, "values"), vout = d.alloc(n * 4, "sorted values");
          Buffer off = d.alloc(offsets.size() * 4, "offsets");
          d.upload(kin, keys.data(), n * sizeof(Key));
          d.upload(vin, values.data(), n * 4);
          d.upload(off, offsets.data(), offsets.size() * 4);
          MvRadixParams p{n, blocks, block_size, shift, has_values, 0, 0, 0, 0, 0, 0};
          d.dispatch(k, (blocks + local - 1) / local, local, {&kin, &kout, &vin, &vout, &off}, p);
          d.finish();
          std::vector<Key> got(n);
          std::vector<uint32_t> got_values(n);
          d.download(kout, got.data(), n * sizeof(Key));
          d.download(vout, got_values.data(), n * 4);
          ASSERT_TRUE(got == expect);
          if (has_values) {
            ASSERT_TRUE(got_values == expect_values);
          }
        }
      }
}

TEST_P(SortTest, StreamingScatterIsTheStableSortByTheDigit) {
  check_streaming_scatter<uint32_t>(dev());
  if (!HasFatalFailure()) check_streaming_scatter<uint64_t>(dev());
}

MV_INSTANTIATE_ON_ALL_DEVICES(SortTest);

}  // namespace
}  // namespace mv::test
