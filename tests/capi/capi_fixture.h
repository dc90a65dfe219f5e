// What the C API tests share: an octahedron mesh in world units, a device opened through the C API for the
// test's device, and the error record of a call.
#pragma once
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "megavox/device.h"
#include "megavox/megavox.h"

namespace mv::test::capi {

// An octahedron of radius 1 around the origin: 6 vertices, 8 triangles.
struct Mesh {
  std::vector<float> positions;
  std::vector<uint32_t> indices;
};
Mesh octahedron();

// mvNewDevice("device=<selector>,...") for `info`, released at scope end.
struct CDevice {
  explicit CDevice(const DeviceInfo& info, const std::string& extra = "");
  ~CDevice() { mvReleaseDevice(handle); }
  CDevice(const CDevice&) = delete;
  CDevice& operator=(const CDevice&) = delete;
  MvDevice handle = nullptr;
};

// Rays from around the grid toward random points inside it, plus misses and rays from inside.
std::vector<MvTraceRay> random_rays(const MvSceneInfo& info, size_t n, uint64_t seed);

}  // namespace mv::test::capi
