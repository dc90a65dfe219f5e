// The device side of ray traversal: one encoded DAG uploaded, and dispatches of the trace and
// secondary-ray kernels (kernels/common/trace.h, secondary.h) over rays in root-cube coordinates.
#pragma once
#include <cstdint>
#include <map>

#include "common/secondary.h"
#include "common/trace_beam.h"
#include "megavox/colour_palette.h"
#include "megavox/device.h"
#include "megavox/encode.h"

namespace mv {

class PageCache;

class TraceEngine {
 public:
  TraceEngine(Device& dev, const EncodedDag& dag);
  // An encoding of `levels` levels read through `cache` (kernel trace_rays_paged, or trace_rays_paged_ssvdag
  // for an ssvdag, whose level starts the cache holds after its page table): traces stamp the cache's current
  // pass; a ray that meets a missing page requests it and stops there (a coarse hit).
  TraceEngine(Device& dev, Encoding encoding, uint32_t levels, PageCache& cache);
  // Paged: whether traces stamp the slots they read (on by default: the _paged kernels). Off (the _whole
  // kernels) only where nothing can be evicted (a cache with a slot for every page, filled in page order:
  // PageCache::preload), so the stamps would go unread.
  void set_usage_stamps(bool on) { stamp_usage_ = on; }

  Device& device() { return dev_; }
  uint32_t levels() const { return levels_; }
  // Where the ssvdag kernel finds each level's start (mv_level_base): by default from the parameters on
  // lavapipe when they hold every level (each load costs a loop over the SIMD lanes there), else from memory
  // (paged: the cache's table). Tests pick each kernel on every device; parameters need a tree of at most
  // 3 + MV_TRACE_PARAM_LEVELS levels (paged: MV_TRACE_PAGED_PARAM_LEVELS).
  enum class LevelStarts { automatic, memory, parameters };
  void set_level_starts(LevelStarts where);
  // A step limit the device can run (lavapipe ends loops at 65535 iterations).
  uint32_t step_limit(uint32_t wanted) const;

  // Traces rays [first, first + count): from `rays` (MV_RAY_FLOATS each) or, with `camera`, the camera's pixel
  // rays. Writes MV_HIT_WORDS per ray into `results`, or with `occlusion` adds 1 to results[i] when ray i hits.
  // With `beam` (camera rays), each ray starts where beam() found its tile's rays may: the same hits.
  void trace(const Buffer* rays, const Buffer* camera, uint32_t first, uint32_t count, uint32_t width, float proj,
             uint32_t max_steps, bool occlusion, Buffer& results, bool beam = false);

  // The beam pre-pass (kernels/common/trace_beam.h) over a frame of `width` x `height` camera rays: where each
  // MV_BEAM_TILE^2 tile's rays may start, written after the camera record in `camera` (beam_camera_floats).
  // `cells`: the coarse grid's cells per axis (a power of two, 4 .. min(2^levels, kBeamMaxCells)), built on first
  // use and kept; `reach`: how far a tile's rays stray from its centre ray per unit t, on each axis; the parent
  // pass over tiles twice as wide likewise (parent_cells = 0: none); `proj`: the frame's LOD factor.
  static constexpr uint32_t kBeamMaxCells = 64;
  void beam(Buffer& camera, uint32_t width, uint32_t height, uint32_t cells, float reach, uint32_t parent_cells,
            float parent_reach, float proj);
  // The camera buffer's floats with the pre-pass: the record, the tiles' starts, the parent tiles'.
  static uint64_t beam_camera_floats(uint32_t width, uint32_t height) {
    return MV_CAMERA_FLOATS + uint64_t{mv_beam_tile_count(width, height, MV_BEAM_TILE)} +
           mv_beam_tile_count(width, height, 2 * MV_BEAM_TILE);
  }
  // The dilated grid of `cells` per axis the pre-pass reads (trace_beam.h's layout), built on first use. Paged,
  // its trace is one of the cache's passes: where a page was missing the cells below count as full (still a
  // proof, a weaker one), and forget_beam_grid() lets the next pass build it again with the pages it loaded.
  const Buffer& beam_grid(uint32_t cells);
  bool has_beam_grid(uint32_t cells) const { return beam_grids_.count(cells) != 0; }
  void forget_beam_grid(uint32_t cells) { beam_grids_.erase(cells); }

  // Voxel colours (resident DAGs): `rgb`, RGB24 per octree node in depth-first order (docs/colour.md), uploaded
  // with the subtree sizes the hit colour walk reads. Throws mv::Error when the entries are not the DAG's octree
  // nodes, or when paged.
  // `palette`, when given (the same colours as stored compressed), is what the device holds instead of raw words.
  void attach_colours(const EncodedDag& dag, const std::vector<uint8_t>& rgb, const ColourPalette* palette = nullptr);
  uint64_t colour_bytes() const { return colours_.bytes(); }  // on the device (0 without colours)
  bool has_colours() const { return !colours_.empty(); }
  // For hit records [first, first + count) of `hits`: each hit's colour, R | G << 8 | B << 16 | 255 << 24, a miss
  // 0, into `out` at the same positions (kernel hit_colours: kernels/common/trace_colour.h).
  void hit_colours(const Buffer& hits, uint32_t first, uint32_t count, Buffer& out);
  // Paged, with the cache's size plane: each hit's depth-first colour entry (MV_NO_ENTRY for a miss, or where a
  // page on its path is not resident), into `out` (kernel hit_entries_paged: kernels/common/trace_colour_paged.h).
  void hit_entries(const Buffer& hits, uint32_t first, uint32_t count, Buffer& out);

  // The primary hits of rays [0, count) that cast secondary rays, listed in order into `listed` (count + 1
  // uint32_t at least); returns how many. Waits, to read the count.
  uint32_t list_secondary(const Buffer& hits, uint32_t count, Buffer& listed);
  // Writes the secondary ray of each listed hit of [first, first + count) of `listed` into `out` at its place in
  // the list (p.first / p.count are set here).
  void secondary(const Buffer* rays, const Buffer* camera, const Buffer& hits, const Buffer& listed,
                 const Buffer* table, uint32_t first, uint32_t count, MvSecondaryParams p, Buffer& out);

 private:
  template <class F>
  void for_each_dispatch(uint32_t first, uint32_t count, F&& dispatch);
  // Items [0, items) of a two-buffer kernel over the work-items, each dispatch's share in p.first / count / block.
  template <class P>
  void dispatch_pair(KernelId id, uint32_t items, const Buffer& a, const Buffer& b, P p);

  Device& dev_;
  uint32_t levels_ = 0;
  uint32_t encoding_ = 0;
  Buffer words_, bricks_, level_offsets_;
  Buffer colour_meta_, colours_;  // attach_colours
  bool starts_in_params_ = false;
  bool starts_fit_params_ = true;  // paged ssvdag: every level start below 2^32 (the parameters' words)
  PageCache* cache_ = nullptr;
  uint32_t page_shift_ = 0;
  bool stamp_usage_ = true;
  bool relative_ = false;  // paged word stream: pointers count from their level's start (non-zero starts)
  MvTraceParams params_{};  // ssvdag level starts; paged, where the runs start
  std::map<uint32_t, Buffer> beam_grids_;  // the beam pre-pass's dilated grids, by cells per axis
};

}  // namespace mv
