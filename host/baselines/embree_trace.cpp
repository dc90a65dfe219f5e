// The triangle ray-tracing baseline: Embree 3's rtcIntersect1 over the source mesh (present only when built in).
#include <algorithm>
#include <chrono>
#include <cmath>

#include "baselines.h"
#include "megavox/error.h"
#include "timing.h"

#if MEGAVOX_HAVE_EMBREE
#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#endif

namespace mv::baseline {

#if MEGAVOX_HAVE_EMBREE
EmbreeResult embree_primary_hits(std::span<const float> positions, std::span<const uint32_t> indices,
                                 const EmbreeFrame& f, uint32_t repeats) {
  EmbreeResult out;
  RTCDevice device = rtcNewDevice(nullptr);
  if (!device) throw Error("bench trace: Embree could not create a device");
  auto t0 = std::chrono::steady_clock::now();
  RTCScene scene = rtcNewScene(device);
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  float* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                         3 * sizeof(float), positions.size() / 3));
  std::copy(positions.begin(), positions.end(), v);
  uint32_t* tri = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                                 3 * sizeof(uint32_t), indices.size() / 3));
  std::copy(indices.begin(), indices.end(), tri);
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene);
  out.build_seconds = seconds_since(t0);
  out.hit.assign(size_t{f.width} * f.height, 0);
  out.trace_seconds = INFINITY;
  for (uint32_t rep = 0; rep < std::max(repeats, 1u); ++rep) {
    auto t1 = std::chrono::steady_clock::now();
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, f.height), [&](const tbb::blocked_range<uint32_t>& rows) {
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);
      for (uint32_t y = rows.begin(); y < rows.end(); ++y)
        for (uint32_t x = 0; x < f.width; ++x) {
          RTCRayHit rh{};
          rh.ray.org_x = f.eye[0];
          rh.ray.org_y = f.eye[1];
          rh.ray.org_z = f.eye[2];
          rh.ray.dir_x = f.dir0[0] + x * f.dx[0] + y * f.dy[0];
          rh.ray.dir_y = f.dir0[1] + x * f.dx[1] + y * f.dy[1];
          rh.ray.dir_z = f.dir0[2] + x * f.dx[2] + y * f.dy[2];
          rh.ray.tnear = 0;
          rh.ray.tfar = INFINITY;
          rh.ray.mask = ~0u;
          rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          rtcIntersect1(scene, &ctx, &rh);
          out.hit[size_t{y} * f.width + x] = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
    });
    out.trace_seconds = std::min(out.trace_seconds, seconds_since(t1));
  }
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
  return out;
}
#else
EmbreeResult embree_primary_hits(std::span<const float>, std::span<const uint32_t>, const EmbreeFrame&, uint32_t) {
  throw Error(missing_note(embree()));
}
#endif

}  // namespace mv::baseline
