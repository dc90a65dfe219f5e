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
    const double sec = std::chrono::duration<double>(clock::now() - t0).count();
    out.passes.push_back({name, rays, sec});
    out.trace_seconds += sec;
  };

  Buffer cam = dev.alloc(sizeof(s.camera), "camera");
  dev.upload(cam, s.camera, sizeof(s.camera));
  Buffer hits = dev.alloc(uint64_t{n} * MV_HIT_WORDS * 4, "primary hits");
  const bool shaded = options.shading == Shading::shaded;
  Buffer rays, counts, table;
  if (shaded) {
    rays = dev.alloc(uint64_t{n} * MV_RAY_FLOATS * 4, "secondary rays");
    counts = dev.alloc(uint64_t{n} * 4, "occlusion counts");
    if (s.ao_samples) {
      table = dev.alloc(s.ao_table.size() * 4, "AO directions");
      dev.upload(table, s.ao_table.data(), s.ao_table.size() * 4);
    }
  }
  res.hits.resize(uint64_t{n} * MV_HIT_WORDS);
  // One frame pass traces every ray of the picture; a paged tracer then loads what it missed, and the next
  // pass traces again, until a pass misses nothing (the picture is then the resident one) or makes no progress.
  for (uint32_t frame_pass = 1;; ++frame_pass) {
    out.passes.clear();
    tracer.begin_pass();
    pass("primary", n, [&] { engine.trace(nullptr, &cam, n, s.width, s.proj, options.max_steps, false, hits); });
    dev.download(hits, res.hits.data(), res.hits.size() * 4);
    out.hits = 0;
    out.coarse_pixels = 0;
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t info = mv_load_hit(res.hits.data(), i).info;
      const bool hit = MV_INFO_STATUS(info) == MV_TRACE_HIT;
      out.hits += hit;
      out.coarse_pixels += hit && MV_INFO_COARSE(info);
    }
    res.shadow.clear();
    res.ao.clear();
    if (shaded && out.hits) {
      dev.fill(counts, 0, uint64_t{n} * 4);
      pass("shadow", out.hits, [&] {
        engine.secondary(nullptr, &cam, hits, nullptr, n, s.shadow, rays);
        engine.trace(&rays, nullptr, n, 0, s.proj, options.max_steps, true, counts);
      });
      res.shadow.resize(n);
      dev.download(counts, res.shadow.data(), uint64_t{n} * 4);
      if (s.ao_samples) {
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
    if (!tracer.paged()) break;
    const CacheUpdateStats st = tracer.end_pass();
    out.cache.push_back(st);
    out.converged = st.requested == 0;
    if (out.converged || st.loaded == 0 || frame_pass == options.cache_passes) break;
  }
  out.image = shade(s, options, res);
  return out;
}

}  // namespace mv
