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
  // Packets: 4 x 4 pixel tiles, the rows of tiles over all threads; lanes past the frame's edge are masked off.
  std::vector<uint8_t> packet_hit(out.hit.size(), 0);
  out.packet_seconds = INFINITY;
  const uint32_t tiles_x = (f.width + 3) / 4, tiles_y = (f.height + 3) / 4;
  for (uint32_t rep = 0; rep < std::max(repeats, 1u); ++rep) {
    auto t1 = std::chrono::steady_clock::now();
    tbb::parallel_for(tbb::blocked_range<uint32_t>(0, tiles_y), [&](const tbb::blocked_range<uint32_t>& rows) {
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);
      alignas(64) RTCRayHit16 rh;
      alignas(64) int valid[16];
      for (uint32_t ty = rows.begin(); ty < rows.end(); ++ty)
        for (uint32_t tx = 0; tx < tiles_x; ++tx) {
          for (uint32_t k = 0; k < 16; ++k) {
            const uint32_t x = 4 * tx + (k & 3), y = 4 * ty + (k >> 2);
            valid[k] = x < f.width && y < f.height ? -1 : 0;
            rh.ray.org_x[k] = f.eye[0];
            rh.ray.org_y[k] = f.eye[1];
            rh.ray.org_z[k] = f.eye[2];
            rh.ray.dir_x[k] = f.dir0[0] + x * f.dx[0] + y * f.dy[0];
            rh.ray.dir_y[k] = f.dir0[1] + x * f.dx[1] + y * f.dy[1];
            rh.ray.dir_z[k] = f.dir0[2] + x * f.dx[2] + y * f.dy[2];
            rh.ray.tnear[k] = 0;
            rh.ray.tfar[k] = INFINITY;
            rh.ray.mask[k] = ~0u;
            rh.ray.time[k] = 0;
            rh.ray.flags[k] = 0;
            rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
          }
          rtcIntersect16(valid, scene, &ctx, &rh);
          for (uint32_t k = 0; k < 16; ++k)
            if (valid[k])
              packet_hit[size_t{4 * ty + (k >> 2)} * f.width + 4 * tx + (k & 3)] =
                  rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
        }
    });
    out.packet_seconds = std::min(out.packet_seconds, seconds_since(t1));
  }
  for (size_t i = 0; i < out.hit.size(); ++i) out.packet_mismatches += packet_hit[i] != out.hit[i];
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
