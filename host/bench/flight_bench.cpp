#include "flight_bench.h"

#include <cmath>
#include <memory>
#include <numbers>

#include "stopwatch.h"
#include "cache/page_cache.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "megavox/trace.h"

namespace mv::bench {

std::vector<Camera> orbit_flight(const Bounds& b, uint32_t frames, double distance, double fov) {
  const Camera iso = view_camera(b, "iso", fov);
  double c[3], r = 0;
  for (int a = 0; a < 3; ++a) c[a] = iso.target[a];
  for (int a = 0; a < 3; ++a) r += (iso.eye[a] - c[a]) * (iso.eye[a] - c[a]);
  r = std::sqrt(r) * distance;
  std::vector<Camera> out;
  for (uint32_t i = 0; i < frames; ++i) {
    const double phi = 2 * std::numbers::pi * i / std::max<uint32_t>(frames, 1);
    Camera cam = iso;
    cam.eye[0] = c[0] + r * 0.8 * std::cos(phi);
    cam.eye[1] = c[1] + r * 0.5;
    cam.eye[2] = c[2] + r * 0.8 * std::sin(phi);
    out.push_back(cam);
  }
  return out;
}

FlightBenchResult run_flight_bench(Device& dev, const std::string& paged_mvx, const std::vector<Camera>& flight,
                                   const RenderOptions& options, uint64_t cache_bytes) {
  FlightBenchResult out;
  const MvxFile file = read_mvx(paged_mvx);  // the level-order stream: today's resident kernel
  Tracer resident(dev, file);
  PagedDag dag = open_paged_mvx(paged_mvx);
  out.pages = dag.pages;
  out.page_words = dag.page_words;
  // a slot: a page, and its size plane when the file's colours stream with it
  const uint64_t slot_bytes = uint64_t{dag.page_words + (dag.colour ? dag.plane_words : 0)} * 4;
  Tracer paged(dev, std::move(dag), cache_bytes);
  out.slots = paged.cache()->config().slots;
  // The address layer's cost is measured through a second cache, as large as one allocation allows (all of the
  // DAG when it fits, like the resident tracer's words: the kernels reach both through device addresses, not
  // bindings): a cache of every page is preloaded, else each view converges in it; either way its last pass
  // reads only resident pages.
  std::unique_ptr<Tracer> warm;
  {
    const uint64_t most = dev.info().max_allocation_bytes ? dev.info().max_allocation_bytes : ~uint64_t{0};
    const uint64_t slots = std::min<uint64_t>(out.pages, (most - PageCache::kDataSpareWords * 4) / slot_bytes);
    try {
      warm = std::make_unique<Tracer>(dev, open_paged_mvx(paged_mvx), slots * slot_bytes);
      out.warm_slots = static_cast<uint32_t>(slots);
    } catch (const Error&) {  // no room beside the resident DAG: no address figure
    }
  }
  {  // both kernels compiled (and PoCL's cache read) before anything is timed; the cache stays cold
    RenderOptions tiny = options;
    tiny.width = 8, tiny.height = 8, tiny.cache_passes = 1;
    render(resident, flight.front(), tiny);
    PagedDag cold = open_paged_mvx(paged_mvx);
    Tracer warmup(dev, std::move(cold), slot_bytes);
    render(warmup, flight.front(), tiny);
  }
  uint64_t used = 0, requested = 0;
  double resident_trace_converged = 0;
  for (const Camera& cam : flight) {
    FlightFrame f;
    auto t0 = Clock::now();
    const RenderResult want = render(resident, cam, options);
    f.resident_seconds = since(t0);
    t0 = Clock::now();
    const RenderResult r = render(paged, cam, options);
    f.paged_seconds = since(t0);
    f.passes = static_cast<uint32_t>(r.cache.size());
    f.converged = r.converged;
    f.identical = r.image.rgb == want.image.rgb;
    const CacheTotals t = cache_totals(r.cache);
    f.manage_seconds = t.manage_seconds;
    f.produce_seconds = t.produce_seconds;
    f.read_ahead_seconds = t.read_ahead_seconds;
    f.pages_read_ahead = t.read_ahead;
    f.pages_loaded = t.loaded;
    f.pages_evicted = t.evicted;
    f.bytes_uploaded = t.bytes_uploaded;
    f.hit_rate = t.hit_rate();
    f.resident_trace_seconds = want.trace_seconds;
    if (warm) {
      // the address layer: this view's last pass over a cache holding all its pages against the resident kernel,
      // the best of kAddressSamples each, taken in pairs whose order alternates, so neither kernel always runs
      // second, and neither gets more tries (the flight's own resident frame is not one: it was one extra)
      RenderOptions once = options;
      once.cache_passes = 1;
      render(*warm, cam, options);  // converge: every page this view reads is resident from here on
      auto trace_seconds = [&](bool paged) {
        return paged ? render(*warm, cam, once).trace_seconds : render(resident, cam, options).trace_seconds;
      };
      double paged_best = 0, resident_best = 0;
      for (int k = 0; k < kAddressSamples; ++k)
        for (int j = 0; j < 2; ++j) {
          const bool paged_turn = (j == 0) == (k % 2 == 0);
          const double sec = trace_seconds(paged_turn);
          double& best = paged_turn ? paged_best : resident_best;
          best = k == 0 ? sec : std::min(best, sec);
        }
      f.last_pass_trace_seconds = paged_best;
      f.resident_best_trace_seconds = resident_best;
      out.last_pass_trace_seconds += paged_best;
      resident_trace_converged += resident_best;
    }
    used += t.used, requested += t.requested;
    out.resident_seconds += f.resident_seconds;
    out.paged_seconds += f.paged_seconds;
    out.manage_seconds += f.manage_seconds;
    out.produce_seconds += f.produce_seconds;
    out.read_ahead_seconds += f.read_ahead_seconds;
    out.pages_read_ahead += f.pages_read_ahead;
    out.resident_trace_seconds += f.resident_trace_seconds;
    out.bytes_uploaded += f.bytes_uploaded;
    out.identical += f.identical;
    out.frames.push_back(f);
  }
  out.manage_share = out.paged_seconds > 0 ? out.manage_seconds / out.paged_seconds : 0;
  out.address_cost = resident_trace_converged > 0 ? out.last_pass_trace_seconds / resident_trace_converged : 0;
  out.hit_rate = used + requested ? double(used) / double(used + requested) : 1.0;
  return out;
}

}  // namespace mv::bench
