// The kernel language layer (kernels/common/mv_lang.h) on every device: 32- and 64-bit atomics on global and
// shared memory, barriers, work-group ids, a work-group histogram, a compare-exchange loop, 2-D launches and
// arguments past Vulkan's push constants. Probe kernels: tests/kernels/lang/, bodies in kernels/common/lang_*.h.
#include <algorithm>
#include <numeric>

#include "bodies/lang_probe.h"
#include "megavox/error.h"
#include "test_kernels.h"
#include "test_support.h"

namespace mv::test {
namespace {

class LangTest : public ::testing::TestWithParam<DeviceInfo> {
 protected:
  Device& dev() { return shared_device(GetParam()); }
};

template <class T>
Buffer upload(Device& d, const std::vector<T>& v, const char* what) {
  Buffer b = d.alloc(std::max<size_t>(v.size(), 1) * sizeof(T), what);
  if (!v.empty()) d.upload(b, v.data(), v.size() * sizeof(T));
  return b;
}

template <class T>
std::vector<T> download(Device& d, const Buffer& b, size_t n) {
  std::vector<T> v(n);
  d.finish();
  d.download(b, v.data(), n * sizeof(T));
  return v;
}

template <class T>
std::vector<T> test_values(size_t n, uint64_t seed) {
  std::vector<T> v;
  if constexpr (sizeof(T) == 8) {
    v = random_u64(n, seed);
  } else {
    v = random_u32(n, seed);
  }
  for (size_t i = 0; i < n; i += 97) v[i] = T(i);  // small values and repeats among the random ones
  return v;
}

// Kernel k for T's width, or a skip with the device's own message when it lacks 64-bit atomics.
template <class T>
Kernel* kernel_for(Device& d, TestKernelId k32, TestKernelId k64, bool has64) {
  if constexpr (sizeof(T) == 8) {
    if (!has64) {
      EXPECT_THROW(test_kernel(d, k64), Error);
      return nullptr;
    }
    return &test_kernel(d, k64);
  } else {
    return &test_kernel(d, k32);
  }
}

template <class T>
void check_global_atomics(Device& d) {
  const uint32_t n = 5000;
  Kernel* k = kernel_for<T>(d, TestKernelId::lang_atomics_k32, TestKernelId::lang_atomics_k64, d.info().atomics64);
  if (!k) GTEST_SKIP() << d.info().name << " lacks 64-bit atomics (the kernel is refused, as checked)";
  const std::vector<T> vals = test_values<T>(n, 11);
  const T start = T(0x5eed);
  Buffer bv = upload(d, vals, "values");
  Buffer bs = upload(d, std::vector<T>{0, T(~T(0)), 0, 0, start, 0}, "slots");
  Buffer bo = upload(d, std::vector<T>(2 * n, 0), "olds");
  d.dispatch(*k, d.groups_for(n, 64), 64, {&bv, &bs, &bo}, MvLangParams{n, 0, 0, 0});
  const std::vector<T> slots = download<T>(d, bs, 6), olds = download<T>(d, bo, 2 * n);
  EXPECT_EQ(slots[0], T(n));
  EXPECT_EQ(slots[1], *std::min_element(vals.begin(), vals.end()));
  EXPECT_EQ(slots[2], *std::max_element(vals.begin(), vals.end()));
  EXPECT_EQ(slots[3], std::accumulate(vals.begin(), vals.end(), T(0), [](T a, T b) { return T(a | b); }));
  EXPECT_EQ(slots[5], std::accumulate(vals.begin(), vals.end(), T(0)));  // the compare-exchange loop's sum
  std::vector<T> added, swapped = {slots[4]}, expect_swapped = vals;
  for (uint32_t i = 0; i < n; ++i) {
    added.push_back(olds[2 * i]);
    swapped.push_back(olds[2 * i + 1]);
  }
  expect_swapped.push_back(start);
  std::sort(added.begin(), added.end());
  for (uint32_t i = 0; i < n; ++i) ASSERT_EQ(added[i], T(i)) << "each add returns a distinct earlier count";
  std::sort(swapped.begin(), swapped.end());
  std::sort(expect_swapped.begin(), expect_swapped.end());
  EXPECT_EQ(swapped, expect_swapped) << "the exchanges pass every value on exactly once";
}

template <class T>
void check_shared_atomics(Device& d) {
  const uint32_t n = 3000, local = 64, groups = (n + local - 1) / local + 2;  // two groups with no item at all
  Kernel* k = kernel_for<T>(d, TestKernelId::lang_shared_atomics_k32, TestKernelId::lang_shared_atomics_k64,
                            d.info().shared_atomics64);
  if (!k) GTEST_SKIP() << d.info().name << " lacks 64-bit shared atomics (the kernel is refused, as checked)";
  const std::vector<T> vals = test_values<T>(n, 12);
  Buffer bv = upload(d, vals, "values");
  Buffer bo = upload(d, std::vector<T>(MV_LANG_SLOTS * groups, 7), "group results");
  d.dispatch(*k, groups, local, {&bv, &bo}, MvLangParams{n, 0, 0, 0});
  const std::vector<T> out = download<T>(d, bo, MV_LANG_SLOTS * groups);
  for (uint32_t g = 0; g < groups; ++g) {
    SCOPED_TRACE("group " + std::to_string(g));
    const uint32_t lo = std::min(n, g * local), hi = std::min(n, lo + local);
    std::vector<T> mine(vals.begin() + lo, vals.begin() + hi);
    const T* r = &out[MV_LANG_SLOTS * g];
    EXPECT_EQ(r[0], T(hi - lo));
    EXPECT_EQ(r[1], mine.empty() ? T(~T(0)) : *std::min_element(mine.begin(), mine.end()));
    EXPECT_EQ(r[2], mine.empty() ? T(0) : *std::max_element(mine.begin(), mine.end()));
    EXPECT_EQ(r[3], std::accumulate(mine.begin(), mine.end(), T(0), [](T a, T b) { return T(a | b); }));
    if (!mine.empty()) EXPECT_NE(std::find(mine.begin(), mine.end(), r[4]), mine.end()) << "last exchange wins";
    EXPECT_EQ(r[5], std::accumulate(mine.begin(), mine.end(), T(0)));
  }
}

TEST_P(LangTest, GlobalAtomics32) { check_global_atomics<uint32_t>(dev()); }
TEST_P(LangTest, GlobalAtomics64) { check_global_atomics<uint64_t>(dev()); }
TEST_P(LangTest, SharedAtomics32) { check_shared_atomics<uint32_t>(dev()); }
TEST_P(LangTest, SharedAtomics64) { check_shared_atomics<uint64_t>(dev()); }

TEST_P(LangTest, WorkGroupHistogram) {
  Device& d = dev();
  const uint32_t n = 100003;
  std::vector<uint32_t> keys = random_u32(n, 13);
  for (uint32_t i = 0; i < n; i += 3) keys[i] = 42;  // one hot bin: many collisions on one shared counter
  std::vector<uint32_t> expect(MV_LANG_BINS, 0);
  for (uint32_t k : keys) ++expect[k & 255];
  Buffer bk = upload(d, keys, "keys");
  Buffer bh = upload(d, std::vector<uint32_t>(MV_LANG_BINS, 0), "histogram");
  for (uint32_t local : {1u, 8u, 64u, 256u}) {
    if (local > d.info().max_work_group_size) continue;
    d.fill(bh, 0, MV_LANG_BINS * 4);
    d.barrier();
    d.dispatch(test_kernel(d, TestKernelId::lang_histogram), 13, local, {&bk, &bh}, MvLangParams{n, 0, 0, 0});
    EXPECT_EQ(download<uint32_t>(d, bh, MV_LANG_BINS), expect) << "work-group size " << local;
  }
}

TEST_P(LangTest, TwoDimensionalLaunch) {
  Device& d = dev();
  const uint32_t width = 37, height = 23, lx = 8, ly = 4;
  const LaunchGrid grid{{(width + lx - 1) / lx, (height + ly - 1) / ly}, {lx, ly}};
  Buffer out = upload(d, std::vector<uint32_t>(2 * width * height, ~0u), "grid");
  d.dispatch(test_kernel(d, TestKernelId::lang_grid2d), grid, {&out}, MvLangParams{0, width, height, 0});
  const std::vector<uint32_t> got = download<uint32_t>(d, out, 2 * width * height);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) {
      const uint32_t cell = y * width + x;
      ASSERT_EQ(got[2 * cell], x | (y << 16)) << x << "," << y;
      ASSERT_EQ(got[2 * cell + 1], (x % lx) | ((y % ly) << 8) | ((x / lx) << 16) | ((y / ly) << 24)) << x << "," << y;
    }
}

// 6 buffers and 96 parameter bytes: past Vulkan's 128 push-constant bytes, so a parameter buffer carries them.
// `dispatches` of them in one recording fill several of its chunks.
void check_arguments_past_the_push_constants(Device& d, uint32_t dispatches) {
  std::vector<Buffer> in;
  std::vector<uint32_t> first;
  for (uint32_t b = 0; b < 5; ++b) {
    first.push_back(1000 * b + 7);
    in.push_back(upload(d, std::vector<uint32_t>{first.back()}, "argument input"));
  }
  Buffer out = upload(d, std::vector<uint32_t>(dispatches, 0), "checksums");
  Kernel& k = test_kernel(d, TestKernelId::lang_args);
  std::vector<uint32_t> expect(dispatches);
  for (uint32_t s = 0; s < dispatches; ++s) {
    MvLangArgsParams p{};
    p.slot = s;
    for (uint32_t w = 0; w < MV_LANG_ARG_WORDS; ++w) p.words[w] = s * 131 + w * 7919;
    d.dispatch(k, 1, 1, {&out, &in[0], &in[1], &in[2], &in[3], &in[4]}, p);
    mv_lang_args(expect.data(), &first[0], &first[1], &first[2], &first[3], &first[4], p);  // the same body
  }
  EXPECT_EQ(download<uint32_t>(d, out, dispatches), expect);
}

TEST_P(LangTest, ArgumentsPastThePushConstants) { check_arguments_past_the_push_constants(dev(), 1000); }

// Profiling submits the recording when its timestamp queries run out (every 4096 dispatches on Vulkan), which
// hands the parameter buffers out again: the arguments stay right across those submissions.
TEST_P(LangTest, ArgumentsPastThePushConstantsWhileProfiling) {
  auto d = Device::open({GetParam().selector(), 64u << 20, true});
  check_arguments_past_the_push_constants(*d, 4500);
}

TEST(LangFeatures, MissingFeaturesAreNamed) {
  DeviceInfo info;
  info.atomics64 = false;
  info.shared_atomics64 = true;
  EXPECT_EQ(rt::missing_features(info, 0), "");
  EXPECT_EQ(rt::missing_features(info, rt::kNeedsSHARED_ATOMICS64), "");
  EXPECT_EQ(rt::missing_features(info, rt::kNeedsATOMICS64 | rt::kNeedsSHARED_ATOMICS64),
            "64-bit atomics on global memory");
  info.shared_atomics64 = false;
  EXPECT_EQ(rt::missing_features(info, rt::kNeedsATOMICS64 | rt::kNeedsSHARED_ATOMICS64),
            "64-bit atomics on global memory, 64-bit atomics on work-group shared memory");
}

MV_INSTANTIATE_ON_ALL_DEVICES(LangTest);

}  // namespace
}  // namespace mv::test
