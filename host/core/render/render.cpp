// The device renderer: primary rays from the camera, then shadow and ambient-occlusion passes through the
// same traversal kernel; shading on the host (frame.h).
#include <algorithm>
#include <chrono>
#include <iterator>

#include "cache/page_cache.h"
#include "megavox/error.h"
#include "megavox/render.h"
#include "megavox/trace.h"
#include "render/frame.h"
#include "timing.h"
#include "trace/trace_engine.h"

namespace mv {

// The smallest band a frame is split into, as a share of its pixels.
constexpr uint32_t kMinTileShare = 256;

RenderResult render(Tracer& tracer, const Camera& camera, const RenderOptions& options) {
  TraceEngine& engine = tracer.engine();
  Device& dev = engine.device();
  const FrameSetup s = frame_setup(tracer.grid(), engine.levels(), camera, options);
  const uint32_t n = s.width * s.height;
  RenderResult out;
  FrameResults res;
  using clock = std::chrono::steady_clock;
  std::vector<RenderPass> passes;  // the current tile pass's
  auto pass = [&](const std::string& name, uint64_t rays, auto&& work) {
    dev.finish();
    auto t0 = clock::now();
    work();
    dev.finish();
    const double sec = seconds_since(t0);
    passes.push_back({name, rays, sec});
    out.trace_seconds += sec;
  };

  const bool shaded = options.shading == Shading::shaded;
  const bool coloured = frame_uses_colours(options) && tracer.has_colours();
  const bool read_ahead = options.read_ahead.value_or(dev.info().massively_parallel);
  // The camera record, then the beam pre-pass's start per tile of the frame
  // (not for heat maps: they show the cost of the whole walk, as the reference renderer does)
  BeamSetup beam =
      options.beam && options.shading != Shading::heat ? beam_setup(s, TraceEngine::kBeamMaxCells) : BeamSetup{};
  // Paged: the grid's coarse trace runs in passes of its own until it met no missing page (its pages are the
  // DAG's top levels); where the cache cannot hold them, rays start at the cube.
  auto grids_built = [&] {
    return engine.has_beam_grid(beam.cells) && (!beam.parent_cells || engine.has_beam_grid(beam.parent_cells));
  };
  for (uint32_t grid_pass = 0; tracer.paged() && beam.cells && !grids_built(); ++grid_pass) {
    if (grid_pass == 4) {
      beam = BeamSetup{};
      break;
    }
    tracer.begin_pass();
    try {
      engine.beam_grid(beam.cells);
      if (beam.parent_cells) engine.beam_grid(beam.parent_cells);
    } catch (const DeviceMemoryError&) {
      beam = BeamSetup{};
    }
    ++out.beam_grid_passes;
    if (tracer.end_pass().requested != 0) {
      engine.forget_beam_grid(beam.cells);
      engine.forget_beam_grid(beam.parent_cells);
    }
  }
  bool beam_pending = beam.cells != 0;
  Buffer cam = dev.alloc((beam.cells ? TraceEngine::beam_camera_floats(s.width, s.height) : MV_CAMERA_FLOATS) * 4,
                         "camera");
  Buffer rays, counts, listed, table;
  if (shaded && s.ao_samples) {
    table = dev.alloc(s.ao_table.size() * 4, "AO directions");
    dev.upload(table, s.ao_table.data(), s.ao_table.size() * 4);
  }
  // The per-pixel buffers hold one tile: the whole frame when the device budget left beside the page cache (and
  // the rest) holds it, else bands of whole rows that do, each traced with its own first pixel (MV_CAMERA_FIRST).
  // (shaded: a secondary ray, an occlusion count and a place in the list of hits that cast them, and the
  // compaction's scratch: flags and positions)
  const uint64_t per_pixel = 4 * (MV_HIT_WORDS + (shaded ? MV_RAY_FLOATS + 4 : 0) + (coloured ? 1 : 0));
  // each buffer rounds up to whole pages (the listing's flags, positions and scan sums are three more); a paged
  // tracer's cache update needs its batch beside them
  const uint64_t keep = 10 * dev.page_bytes() + (tracer.paged() ? tracer.cache()->update_scratch_bytes() : 0);
  const uint64_t budget = dev.memory_budget(), used = dev.memory_used();
  const uint64_t left = budget > used + keep ? budget - used - keep : 0;
  uint32_t rows = static_cast<uint32_t>(std::clamp<uint64_t>(left / (per_pixel * s.width), 1, s.height));
  Buffer hits, colours;
  for (;;) {  // fewer rows when the pool cannot place them (its pages are carved out of a few arenas)
    try {
      hits = dev.alloc(uint64_t{rows} * s.width * MV_HIT_WORDS * 4, "primary hits");
      if (shaded) {
        rays = dev.alloc(uint64_t{rows} * s.width * MV_RAY_FLOATS * 4, "secondary rays");
        counts = dev.alloc(uint64_t{rows} * s.width * 4, "occlusion counts");
        listed = dev.alloc((uint64_t{rows} * s.width + 1) * 4, "hits casting secondary rays");
      }
      if (coloured) colours = dev.alloc(uint64_t{rows} * s.width * 4, "hit colours");
      break;
    } catch (const DeviceMemoryError&) {
      hits = Buffer(), rays = Buffer(), counts = Buffer(), listed = Buffer(), colours = Buffer();
      if (rows == 1)
        throw DeviceMemoryError("render: one row of " + std::to_string(s.width) + " pixels needs " +
                                format_bytes(per_pixel * s.width) + " of device memory, and " + format_bytes(left) +
                                " of the " + format_bytes(budget) +
                                " budget is left beside the page cache (and its update's batch) and the DAG: raise "
                                "the device memory budget, or lower the page cache budget or the picture width",
                                setting_device_memory | setting_cache_memory | setting_width);
      rows /= 2;
    }
  }
  const uint32_t tile_pixels = rows * s.width;
  if (shaded) {
    res.shadow.assign(n, 0);
    if (s.ao_samples) res.ao.assign(n, 0);
  }
  res.hits.resize(uint64_t{n} * MV_HIT_WORDS);
  if (coloured) res.colours.assign(n, 0);

  // One pass over the pixels [first, first + count) (a band of rows): primary rays, then for their hits the
  // shadow and AO rays; the results land in `res` at those pixels.
  struct Tile {
    uint32_t first, count;
  };
  struct TileHits {
    uint64_t hits = 0, coarse = 0, steps = 0, hit_steps = 0;
  };
  auto trace_tile = [&](const Tile& t) {
    TileHits h;
    float tile_cam[MV_CAMERA_FLOATS];
    std::copy(std::begin(s.camera), std::end(s.camera), tile_cam);
    tile_cam[MV_CAMERA_FIRST] = MV_BITSF(t.first);
    dev.upload(cam, tile_cam, sizeof tile_cam);
    pass("primary", t.count, [&] {
      try {  // an optimization: where its grid's one-off scratch does not fit the budget, rays start at the cube
        if (beam_pending)
          engine.beam(cam, s.width, s.height, beam.cells, beam.reach, beam.parent_cells, beam.parent_reach, s.proj);
      } catch (const DeviceMemoryError&) {
        beam = BeamSetup{};
      }
      beam_pending = false;
      engine.trace(nullptr, &cam, 0, t.count, s.width, s.proj, options.max_steps, false, hits, beam.cells != 0);
    });
    dev.download(hits, res.hits.data() + uint64_t{t.first} * MV_HIT_WORDS, uint64_t{t.count} * MV_HIT_WORDS * 4);
    if (coloured) {
      // (paged: before the pass's update, while the pages the primary rays read are resident)
      pass("colour", t.count, [&] { tracer.hit_colours(hits, t.count, colours, res.colours.data() + t.first); });
    }
    for (uint32_t i = t.first; i < t.first + t.count; ++i) {
      const MvHit r = mv_load_hit(res.hits.data(), i);
      const bool hit = MV_INFO_STATUS(r.info) == MV_TRACE_HIT;
      h.hits += hit;
      h.coarse += hit && MV_INFO_COARSE(r.info);
      h.steps += r.steps;
      h.hit_steps += hit ? r.steps : 0;
    }
    if (!shaded) return h;
    // A tile traced again through the cache may list other pixels: the counts of the pass before go first.
    std::fill_n(res.shadow.begin() + t.first, t.count, 0u);
    if (s.ao_samples) std::fill_n(res.ao.begin() + t.first, t.count, 0u);
    if (!h.hits) return h;
    if (read_ahead) tracer.read_ahead();  // the primary rays' missing pages read while shadow and AO trace
    // Only hits on a face cast rays: they are listed (compacted) on the device, and each pass traces just those,
    // counting into the list's order; the counts go back to their pixels here. The listing is timed with the
    // shadow pass, the first that needs it.
    uint32_t cast = 0;
    pass("shadow", 0, [&] {
      cast = engine.list_secondary(hits, t.count, listed);
      if (cast == 0) return;
      dev.fill(counts, 0, uint64_t{cast} * 4);
      engine.secondary(nullptr, &cam, hits, listed, nullptr, 0, cast, s.shadow, rays);
      engine.trace(&rays, nullptr, 0, cast, 0, s.proj, options.max_steps, true, counts);
    });
    passes.back().rays = cast;
    if (cast == 0) return h;
    std::vector<uint32_t> at(cast), got(cast);
    dev.download(listed, at.data(), uint64_t{cast} * 4);
    auto scatter = [&](uint32_t* into) {
      dev.download(counts, got.data(), uint64_t{cast} * 4);
      for (uint32_t j = 0; j < cast; ++j) into[t.first + at[j]] = got[j];
    };
    scatter(res.shadow.data());
    if (s.ao_samples) {
      dev.fill(counts, 0, uint64_t{cast} * 4);
      pass("ao", uint64_t{cast} * s.ao_samples, [&] {
        for (uint32_t k = 0; k < s.ao_samples; ++k) {
          MvSecondaryParams p = s.ao;
          p.sample_k = k;
          engine.secondary(nullptr, &cam, hits, listed, &table, 0, cast, p, rays);
          engine.trace(&rays, nullptr, 0, cast, 0, s.proj, options.max_steps, true, counts);
        }
      });
      scatter(res.ao.data());
    }
    return h;
  };

  // A tile pass traces every ray of its pixels; a paged tracer then loads what they missed, and the next pass
  // traces again, until a pass misses nothing (those pixels are then the resident render's) or makes no
  // progress. A tile whose pages do not fit the cache (its pass used and requested more pages than there are
  // slots) is halved and its halves rendered in turn, down to 1/kMinTileShare of the frame: then a view whose pages
  // exceed the cache still converges to the resident picture, a band at a time. The first tiles are the
  // bands the per-pixel buffers hold.
  const uint32_t min_tile = std::max<uint32_t>(64, n / kMinTileShare);
  std::vector<Tile> pending;  // a stack: the next tile at the back, bands in row order
  for (uint32_t first = (n - 1) / tile_pixels * tile_pixels;; first -= tile_pixels) {
    pending.push_back({first, std::min(tile_pixels, n - first)});
    if (first == 0) break;
  }
  out.converged = true;
  while (!pending.empty()) {
    const Tile t = pending.back();
    pending.pop_back();
    TileHits h;
    bool done = !tracer.paged(), split = false;
    for (uint32_t tile_pass = 1;; ++tile_pass) {
      passes.clear();
      tracer.begin_pass();
      h = trace_tile(t);
      if (done) break;
      const CacheUpdateStats st = tracer.end_pass();
      out.cache.push_back(st);
      done = st.requested == 0;
      split = !done && st.over_capacity && t.count >= 2 * min_tile;
      if (done || split || st.loaded == 0 || tile_pass == options.cache_passes) break;
    }
    if (split) {
      const uint32_t half = t.count / 2;
      pending.push_back({t.first + half, t.count - half});
      pending.push_back({t.first, half});
      continue;
    }
    ++out.tiles;
    out.converged = out.converged && done;
    out.hits += h.hits;
    out.primary_steps += h.steps;
    out.hit_steps += h.hit_steps;
    out.coarse_pixels += h.coarse;
    out.passes.insert(out.passes.end(), passes.begin(), passes.end());
  }
  out.image = shade(s, options, res);
  return out;
}

}  // namespace mv
