#include "capi_fixture.h"

#include <random>

namespace mv::test::capi {

Mesh octahedron() {
  return {{1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1},
          {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5}};
}

CDevice::CDevice(const DeviceInfo& info, const std::string& extra) {
  const std::string config = "device=" + info.selector() + (extra.empty() ? "" : "," + extra);
  handle = mvNewDevice(config.c_str());
  if (!handle) ADD_FAILURE() << "mvNewDevice(" << config << "): " << mvGetDeviceLastErrorMessage(nullptr);
}

std::vector<MvTraceRay> random_rays(const MvSceneInfo& info, size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<float> unit(0, 1), sym(-1, 1);
  const double side = info.voxelSize * info.resolution;
  std::vector<MvTraceRay> rays(n);
  for (size_t i = 0; i < n; ++i) {
    MvTraceRay& r = rays[i];
    for (int a = 0; a < 3; ++a) {
      const double target = info.origin[a] + unit(rng) * side;
      r.org[a] = static_cast<float>(i % 5 == 4 ? target : info.origin[a] + side * (0.5 + 1.5 * sym(rng)));
      r.dir[a] = static_cast<float>(i % 5 == 4 ? sym(rng) : target - r.org[a]);
    }
    if (i % 7 == 3) r.dir[0] = r.dir[1] = 0, r.dir[2] = r.org[2] > 0 ? 1.0f : -1.0f;  // away (a miss, mostly)
    r.tmax = i % 11 == 5 ? 0.01f : INFINITY;
  }
  return rays;
}

}  // namespace mv::test::capi
