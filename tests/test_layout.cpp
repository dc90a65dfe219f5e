// Layout contracts (kernels/common/mv_lang.h): every struct the host shares with kernels, as each device sees
// it. The probe kernels (tests/kernels/bodies/layout_probe.h) get a struct whose word k is MV_PROBE_WORD(k) and write
// back each field; the host's run of the same probe says what they must write.
#include <array>
#include <cstring>

#include "bodies/layout_probe.h"
#include "test_kernels.h"
#include "test_support.h"

namespace mv::test {
namespace {

class LayoutTest : public ::testing::TestWithParam<DeviceInfo> {};

template <class T>
void expect_same_layout(Device& dev, bool has_offsets, TestKernelId kernel, void (*host_probe)(MvBufU32, T)) {
  SCOPED_TRACE(test_kernel(dev, kernel).name());
  static_assert(sizeof(T) % 4 == 0);
  std::array<uint32_t, sizeof(T) / 4> words;
  for (uint32_t k = 0; k < words.size(); ++k) words[k] = MV_PROBE_WORD(k);
  T p;
  std::memcpy(&p, words.data(), sizeof(T));
  std::vector<uint32_t> want(MV_PROBE_WORDS, 0), got(MV_PROBE_WORDS, 0);
  host_probe(want.data(), p);
  ASSERT_EQ(want[0], words.size()) << "the probe lists every field";
  for (uint32_t k = 0; k < want[0]; ++k) ASSERT_EQ(want[2 + k], words[k]) << "field " << k << " is word " << k;

  Buffer out = dev.alloc(MV_PROBE_WORDS * 4, "layout probe");
  dev.fill(out, 0, MV_PROBE_WORDS * 4);
  dev.barrier();
  dev.dispatch(test_kernel(dev, kernel), 1, 1, {&out}, p);
  dev.finish();
  dev.download(out, got.data(), MV_PROBE_WORDS * 4);
  ASSERT_EQ(got[0], want[0]);
  for (uint32_t k = 0; k < want[0]; ++k) EXPECT_EQ(got[2 + k], want[2 + k]) << "field " << k << "'s value";
  if (!has_offsets) return;  // GLSL: no sizeof, no addresses; the values alone tell
  EXPECT_EQ(got[1], want[1]) << "size";
  for (uint32_t k = 0; k < want[0]; ++k)
    EXPECT_EQ(got[2 + MV_PROBE_FIELDS + k], want[2 + MV_PROBE_FIELDS + k]) << "field " << k << "'s offset";
}

TEST_P(LayoutTest, SharedStructsMatchTheHost) {
  Device& dev = shared_device(GetParam());
  const bool offsets = GetParam().backend == "opencl";
  expect_same_layout(dev, offsets, TestKernelId::probe_morton_params, mv_probe_morton_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_radix_params, mv_probe_radix_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_scan_params, mv_probe_scan_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_unique_params, mv_probe_unique_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_cache_params, mv_probe_cache_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_lang_params, mv_probe_lang_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_voxelize_params, mv_probe_voxelize_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_dag_params, mv_probe_dag_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_trace_params, mv_probe_trace_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_secondary_params, mv_probe_secondary_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_beam_params, mv_probe_beam_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_ray, mv_probe_ray);
  expect_same_layout(dev, offsets, TestKernelId::probe_hit, mv_probe_hit);
  expect_same_layout(dev, offsets, TestKernelId::probe_point_params, mv_probe_point_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_splat_params, mv_probe_splat_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_min_cut_params, mv_probe_min_cut_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_min_cut_regions_params, mv_probe_min_cut_regions_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_mask_post_params, mv_probe_mask_post_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_seg_params, mv_probe_seg_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_rep_params, mv_probe_rep_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_grabcut_params, mv_probe_grabcut_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_gather_params, mv_probe_gather_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_colour_params, mv_probe_colour_params);
  expect_same_layout(dev, offsets, TestKernelId::probe_quantize_params, mv_probe_quantize_params);
}

MV_INSTANTIATE_ON_ALL_DEVICES(LayoutTest);

}  // namespace
}  // namespace mv::test
