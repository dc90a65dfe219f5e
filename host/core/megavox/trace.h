// megavox — ray queries against an encoded voxel DAG (svo, svdag, ussvdag or ssvdag), run on a device.
//
// Rays are in the model's own units (the .mvx world-to-grid transform). A hit is the first voxel the ray
// enters: origin + t * direction, t in units of the direction's length (pass unit directions to get
// distances). Cells are half-open like the voxelizer's ([i, i+1)); when a ray crosses several boundaries at
// the same t, the x crossing comes first, then y, then z. Results are the same bytes on every device and
// equal those of a plain voxel-by-voxel DDA (host/ref/trace_reference.h), which the tests check.
#pragma once
#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "megavox/cache_stats.h"
#include "megavox/device.h"
#include "megavox/mvx.h"
#include "megavox/ray.h"

namespace mv {

class TraceEngine;
class PageCache;

// A DAG in pages (a paged .mvx, version 3 on: any encoding): its shape and a reader of page `page` into
// `words` (page_words of them), called by the cache's producer. The reader throws mv::Error when it cannot;
// the page stays missing and tracing goes on.
struct PagedDag {
  GridTransform grid;
  Bounds bounds;  // of the input model, in its own units
  Encoding encoding = Encoding::svdag;
  uint32_t levels = 0;
  uint32_t page_words = 0;  // a power of two
  uint32_t pages = 0;
  // Where its levels start in the paged stream (levels + 1 entries): an ssvdag's (host/formats/paging/paged_ssvdag.h),
  // a word stream's whose pointers count from them (paged_stream.h, level order); empty: absolute pointers.
  std::vector<uint64_t> level_starts;
  bool has_colours = false;  // the file has voxel colours
  // With colours (a version 5 file): the size plane's words a page (0: none), a reader of page `page` of it, and
  // entry e's colour (R | G << 8 | B << 16; throws past the entries), so that hits through the cache find theirs.
  uint32_t plane_words = 0;
  uint64_t colour_entries = 0;  // with colours: every octree node's
  std::function<void(uint32_t page, std::span<uint32_t> words)> read_sizes;
  std::function<uint32_t(uint64_t entry)> colour;
  uint64_t voxels = 0;       // of the model
  uint64_t words = 0;        // of the paged stream (pages * page_words, less the last page's padding)
  std::function<void(uint32_t page, std::span<uint32_t> words)> read;
};

// Uploads one encoded DAG to a device and answers batches of rays with the same kernel the renderer uses.
// A paged .mvx (version 3) opened by memory map, its pages read (and checked against the page index) on
// demand. Throws mv::Error for a file that is not paged (versions 1 and 2, unpaged files: they render resident).
PagedDag open_paged_mvx(const std::string& path);
// Whether `path` is a paged voxel .mvx (what open_paged_mvx opens); throws mv::Error when it is no voxel .mvx.
bool is_paged_mvx(const std::string& path);

class Tracer {
 public:
  // Uploads the file's voxel colours too, when it has them and `colours` is set.
  Tracer(Device& dev, const MvxFile& file, bool colours = true);
  // Streams `dag` through a device page cache of `cache_bytes` (whole pages; counted in the device budget):
  // only the pages rays touch are loaded. Throws mv::Error when cache_bytes holds no page. A cache with room
  // for every page is, with `preload`, filled whole here instead, in page order (preloaded() tells how it went):
  // then the traversal resolves the DAG as one run of pages, the resident path.
  Tracer(Device& dev, PagedDag dag, uint64_t cache_bytes, bool preload = true);
  ~Tracer();
  Tracer(const Tracer&) = delete;
  Tracer& operator=(const Tracer&) = delete;

  // Paged: passes over the batch until no ray misses a page (or options.max_passes); the hits equal those of
  // the resident DAG once it converges. last_passes() tells what each pass loaded.
  // `colours`, when given and the file has voxel colours (has_colours()), receives one RGBA word per ray
  // (R | G << 8 | B << 16 | A << 24): the hit cell's colour, a voxel's or, at a coarser level, the mean below it,
  // with A = 255; 0 for a miss. Without colours in the file it is left empty.
  std::vector<RayHit> trace(const std::vector<Ray>& rays, const TraceOptions& options = {},
                            std::vector<uint32_t>* colours = nullptr);
  // Whether hits carry colours: a resident tracer of a file with voxel colours, or a paged one of a file with its
  // size plane too (a hit whose path left the cache, as after max_passes, gets 0).
  bool has_colours() const;
  // The colours of hit records [0, count) of `hits` into out (as trace's), through `scratch` (count words on the
  // device): resident, the colour kernel's; paged, each hit's entry found through the pages the last pass left
  // resident (a coarse hit's cell too: the mean below it), its colour read from the file.
  void hit_colours(const Buffer& hits, uint32_t count, Buffer& scratch, uint32_t* out);

  TraceEngine& engine() { return *engine_; }
  const GridTransform& grid() const { return grid_; }

  // The page cache of a paged tracer (null when resident): a pass starts with begin_pass(), traces through
  // engine(), and ends with end_pass(), the cache's update (loads what the pass missed).
  bool paged() const { return cache_ != nullptr; }
  PageCache* cache() { return cache_.get(); }
  void begin_pass();
  CacheUpdateStats end_pass();
  // Paged: reads the pages the current pass has missed so far (as many as the cache has slots) on a thread of its
  // own while the device goes on tracing (the renderer calls it between the primary and the shadow rays);
  // end_pass() then takes them from there instead of the file. Does nothing when resident.
  void read_ahead();
  const std::vector<CacheUpdateStats>& last_passes() const { return passes_; }
  // The loads of the constructor's preload, summed (all zero when there was none).
  const CacheUpdateStats& preloaded() const { return preloaded_; }

 private:
  struct PagesRead {
    std::vector<uint32_t> pages;  // in page order
    std::vector<uint32_t> words;  // page_words for each
    std::vector<uint8_t> ok;
    double seconds = 0;
  };
  // Page `page` into `words`: its nodes, then (with a plane) its size plane.
  void read_page(uint32_t page, std::span<uint32_t> words) const;
  GridTransform grid_;
  PagedDag paged_;
  std::unique_ptr<PageCache> cache_;
  std::unique_ptr<TraceEngine> engine_;
  std::vector<CacheUpdateStats> passes_;
  CacheUpdateStats preloaded_;
  std::future<PagesRead> ahead_;
};

}  // namespace mv
