// The launch capabilities each backend fills in DeviceInfo, which host code shapes its dispatches from.
#include <gtest/gtest.h>

#include <cctype>

#include "primitives/launch_shape.h"
#include "test_support.h"

namespace mv::test {
namespace {

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

TEST(DeviceCaps, EveryDeviceFillsItsLaunchShape) {
  for (const DeviceInfo& d : all_devices()) {
    SCOPED_TRACE(d.selector() + " " + d.name);
    EXPECT_GE(d.simd_width, 1u);
    EXPECT_GE(d.preferred_work_group_size, 1u);
    EXPECT_LE(d.preferred_work_group_size, d.max_work_group_size);
    EXPECT_EQ(d.massively_parallel, d.type == "gpu");
    EXPECT_EQ(block_shape(d, 1 << 20).local_size, d.preferred_work_group_size);
  }
}

TEST(DeviceCaps, CpuDevicesAsMeasured) {
  for (const DeviceInfo& d : all_devices()) {
    SCOPED_TRACE(d.selector() + " " + d.name);
    if (d.backend == "vulkan" && lower(d.name).find("llvmpipe") != std::string::npos) {
      // lavapipe: 8 lanes, loads run lane by lane, loops capped at 65535 iterations.
      EXPECT_EQ(d.simd_width, 8u);
      EXPECT_EQ(d.preferred_work_group_size, 8u);
      EXPECT_FALSE(d.cheap_parameter_loads);
      EXPECT_EQ(d.max_loop_iterations, 65535u);
    }
    if (d.backend == "opencl" && d.type == "cpu") {
      // PoCL runs a work-group's items as a loop: one item per group, cheap loads, no loop cap.
      EXPECT_EQ(d.preferred_work_group_size, 1u);
      EXPECT_TRUE(d.cheap_parameter_loads);
      EXPECT_EQ(d.max_loop_iterations, 0u);
    }
  }
}

}  // namespace
}  // namespace mv::test
