// The device renderer: primary rays from the camera, then shadow and ambient-occlusion passes through the
// same traversal kernel; shading on the host (frame.h).
#include <chrono>

#include "megavox/error.h"
#include "megavox/render.h"
#include "megavox/trace.h"
#include "render/frame.h"
#include "trace/trace_engine.h"

namespace mv {

RenderResult render(Tracer& tracer, const Camera& camera, const RenderOptions& options) {
  TraceEngine& engine = tracer.engine();
  Device& dev = engine.device();
  const FrameSetup s = frame_setup(tracer.grid(), engine.levels(), camera, options);
  const uint32_t n = s.width * s.height;
  RenderResult out;
  FrameResults res;
  using clock = std::chrono::steady_clock;
  auto pass = [&](const std::string& name, uint64_t rays, auto&& work) {
    dev.finish();
    auto t0 = clock::now();
    work();
    dev.finish();
    out.passes.push_back({name, rays, std::chrono::duration<double>(clock::now() - t0).count()});
  };

  Buffer cam = dev.alloc(sizeof(s.camera), "camera");
  dev.upload(cam, s.camera, sizeof(s.camera));
  Buffer hits = dev.alloc(uint64_t{n} * MV_HIT_WORDS * 4, "primary hits");
  pass("primary", n, [&] { engine.trace(nullptr, &cam, n, s.width, s.proj, options.max_steps, false, hits); });
  res.hits.resize(uint64_t{n} * MV_HIT_WORDS);
  dev.download(hits, res.hits.data(), res.hits.size() * 4);
  for (uint32_t i = 0; i < n; ++i) out.hits += MV_INFO_STATUS(mv_load_hit(res.hits.data(), i).info) == MV_TRACE_HIT;

  if (options.shading == Shading::shaded && out.hits) {
    Buffer rays = dev.alloc(uint64_t{n} * MV_RAY_FLOATS * 4, "secondary rays");
    Buffer counts = dev.alloc(uint64_t{n} * 4, "occlusion counts");
    dev.fill(counts, 0, uint64_t{n} * 4);
    pass("shadow", out.hits, [&] {
      engine.secondary(nullptr, &cam, hits, nullptr, n, s.shadow, rays);
      engine.trace(&rays, nullptr, n, 0, s.proj, options.max_steps, true, counts);
    });
    res.shadow.resize(n);
    dev.download(counts, res.shadow.data(), uint64_t{n} * 4);
    if (s.ao_samples) {
      Buffer table = dev.alloc(s.ao_table.size() * 4, "AO directions");
      dev.upload(table, s.ao_table.data(), s.ao_table.size() * 4);
      dev.fill(counts, 0, uint64_t{n} * 4);
      pass("ao", out.hits * s.ao_samples, [&] {
        for (uint32_t k = 0; k < s.ao_samples; ++k) {
          MvSecondaryParams p = s.ao;
          p.sample_k = k;
          engine.secondary(nullptr, &cam, hits, &table, n, p, rays);
          engine.trace(&rays, nullptr, n, 0, s.proj, options.max_steps, true, counts);
        }
      });
      res.ao.resize(n);
      dev.download(counts, res.ao.data(), uint64_t{n} * 4);
    }
  }
  out.image = shade(s, options, res);
  return out;
}

}  // namespace mv
