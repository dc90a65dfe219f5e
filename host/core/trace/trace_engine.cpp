// Host side of ray traversal (kernel bodies: kernels/common/trace.h, secondary.h).
#include "trace/trace_engine.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <future>
#include <string>
#include <thread>

#include "cache/page_cache.h"
#include "megavox/error.h"
#include "megavox/segmented.h"
#include "megavox/trace.h"
#include "timing.h"
#include "trace/trace_layout.h"
#include "common/trace_beam.h"
#include "common/trace_colour_paged.h"

namespace mv {

TraceEngine::TraceEngine(Device& dev, const EncodedDag& dag) : dev_(dev), levels_(dag.levels) {
  encoding_ = static_cast<uint32_t>(dag.encoding);
  if (dag.levels == 0 || dag.levels > 21) throw Error("trace: the DAG has " + std::to_string(dag.levels) + " levels");
  const bool ssvdag = dag.encoding == Encoding::ssvdag;
  if (ssvdag ? dag.inner.empty() : dag.words.empty()) throw Error("trace: the DAG is empty");
  if (ssvdag && dag.inner.size() >= (uint64_t{1} << 32)) throw Error("trace: the ssvdag stream exceeds 2^32 words");
  auto upload = [&](const std::vector<uint32_t>& v, const char* what) {
    Buffer b = dev.alloc(std::max<size_t>(v.size(), 1) * 4, what);
    if (!v.empty()) dev.upload(b, v.data(), v.size() * 4);
    return b;
  };
  words_ = upload(trace_words(dag), ssvdag ? "ssvdag inner nodes" : "DAG words");
  if (ssvdag) {
    bricks_ = upload(trace_bricks(dag), "ssvdag bricks");
    level_offsets_ = upload(trace_level_offsets(dag), "ssvdag level offsets");
  }
  set_trace_levels(params_, dag);
  set_level_starts(LevelStarts::automatic);
}

TraceEngine::TraceEngine(Device& dev, Encoding encoding, uint32_t levels, PageCache& cache)
    : dev_(dev), levels_(levels), encoding_(static_cast<uint32_t>(encoding)), cache_(&cache) {
  if (levels == 0 || levels > 21) throw Error("trace: the DAG has " + std::to_string(levels) + " levels");
  const PageCacheConfig& c = cache.config();
  if (c.page_words < 16 || (c.page_words & (c.page_words - 1)) != 0)
    throw Error("trace: pages of " + std::to_string(c.page_words) + " words; paged tracing needs a power of two >= 16");
  page_shift_ = static_cast<uint32_t>(__builtin_ctz(c.page_words));
  params_.level_base[MV_TRACE_PAGE_RUNS] = cache.runs_at();
  // the levels' 64-bit starts, low word first, between the page table and the runs (the kernel finds them from
  // the runs); a word stream's pointers count from them (zeros: absolute pointers)
  if (c.table_tail.size() != 2u * (levels + 1u)) throw Error("trace: a paged DAG needs its level starts after the page table");
  for (uint32_t w : c.table_tail) relative_ = relative_ || (encoding != Encoding::ssvdag && w != 0);
  if (encoding == Encoding::ssvdag) {
    // inner nodes are addressed in 16-bit words of the slots; the level starts lie between the page table and
    // the runs (the kernel finds them from the runs), and the parameters carry the first ones too
    if (uint64_t{c.slots} * c.page_words >= (uint64_t{1} << 31))
      throw Error("trace: a paged ssvdag addresses at most 2^31 words of cache slots (8 GiB)");
    if (levels < 3) throw Error("trace: a paged ssvdag has at least 3 levels");
    if (c.table_tail[4] != 0 || c.table_tail[5] != 0) throw Error("trace: a paged ssvdag's bricks start at word 0");
    // the parameters carry starts below 2^32 16-bit words only; past that the walk reads them from the table
    for (uint32_t k = 0; k < MV_TRACE_PAGED_PARAM_LEVELS && 3 + k <= levels; ++k) {
      params_.level_base[k] = c.table_tail[2 * (3 + k)];
      starts_fit_params_ = starts_fit_params_ && c.table_tail[2 * (3 + k) + 1] == 0;
    }
    set_level_starts(LevelStarts::automatic);
  }
}

void TraceEngine::set_level_starts(LevelStarts where) {
  const DeviceInfo& info = dev_.info();
  const bool fits = mv_trace_params_hold_levels(levels_, cache_ != nullptr) && starts_fit_params_;
  if (where == LevelStarts::parameters && !fits)
    throw Error("trace: the parameters hold level starts for at most " +
                std::to_string(3 + (cache_ ? MV_TRACE_PAGED_PARAM_LEVELS : MV_TRACE_PARAM_LEVELS)) +
                " levels, each starting below 2^32 16-bit words");
  starts_in_params_ = where == LevelStarts::parameters ||
                      (where == LevelStarts::automatic && fits && !info.cheap_parameter_loads);
}

uint32_t TraceEngine::step_limit(uint32_t wanted) const {
  uint32_t cap = dev_.info().max_loop_iterations;
  return cap ? std::min(wanted, cap - 16) : wanted;
}

// One ray per work-item where the driver caps loop iterations (lavapipe), so a work-item's traversal loop
// never sums over several rays; elsewhere grid-stride: a few groups per hardware thread on CPUs, 64-wide
// groups on GPUs.
// CPU devices without a loop cap (PoCL) give each work-item a contiguous block of rays: neighbouring rays
// walk the same nodes, so the block stays in cache; 64 blocks per hardware thread keep the load balanced.
template <class F>
void TraceEngine::for_each_dispatch(uint32_t begin, uint32_t count, F&& dispatch) {
  const DeviceInfo& info = dev_.info();
  const bool gpu = info.massively_parallel;
  const uint32_t local = std::max<uint32_t>(info.preferred_work_group_size, 1);
  const uint64_t max_groups = std::max<uint32_t>(info.max_groups, 1);
  const uint64_t per_dispatch = info.max_loop_iterations ? max_groups * local : count;
  const uint32_t threads = std::max<uint32_t>({info.compute_units, std::thread::hardware_concurrency(), 1u});
  for (uint64_t done = 0; done < count; done += per_dispatch) {
    const uint64_t first = begin + done;
    uint32_t n = static_cast<uint32_t>(std::min<uint64_t>(per_dispatch, count - done));
    uint64_t groups = (uint64_t{n} + local - 1) / local;
    uint32_t block = 0;
    if (!info.max_loop_iterations && !gpu) {
      groups = std::min<uint64_t>(groups, uint64_t{threads} * 64);
      block = static_cast<uint32_t>((n + groups * local - 1) / (groups * local));
    } else if (!info.max_loop_iterations) {
      groups = std::min<uint64_t>(groups, max_groups);
    }
    dispatch(static_cast<uint32_t>(first), n, static_cast<uint32_t>(groups), local, block);
  }
}

void TraceEngine::trace(const Buffer* rays, const Buffer* camera, uint32_t first_ray, uint32_t count, uint32_t width,
                        float proj,
                        uint32_t max_steps, bool occlusion, Buffer& results, bool beam) {
  const bool ssvdag = encoding_ == static_cast<uint32_t>(Encoding::ssvdag);
  const Buffer* bricks = ssvdag ? &bricks_ : nullptr;
  const KernelId paged_ssvdag =
      starts_in_params_ ? (stamp_usage_ ? KernelId::trace_rays_paged_ssvdag_params
                                        : KernelId::trace_rays_paged_ssvdag_whole_params)
                        : (stamp_usage_ ? KernelId::trace_rays_paged_ssvdag : KernelId::trace_rays_paged_ssvdag_whole);
  const KernelId paged_words = relative_ ? (stamp_usage_ ? KernelId::trace_rays_paged_relative
                                                         : KernelId::trace_rays_paged_whole_relative)
                                        : (stamp_usage_ ? KernelId::trace_rays_paged : KernelId::trace_rays_paged_whole);
  const KernelId paged = ssvdag ? paged_ssvdag : paged_words;
  Kernel& k = dev_.kernel(cache_              ? paged
                          : !bricks           ? KernelId::trace_rays
                          : starts_in_params_ ? KernelId::trace_rays_ssvdag_params
                                              : KernelId::trace_rays_ssvdag);
  const Buffer* offsets = bricks ? &level_offsets_ : nullptr;
  for_each_dispatch(first_ray, count, [&](uint32_t first, uint32_t n, uint32_t groups, uint32_t local, uint32_t block) {
    MvTraceParams p = params_;
    p.block = block;
    p.first = first;
    p.count = n;
    p.mode = MV_TRACE_MODE(levels_, camera ? 1u : 0u, occlusion ? 1u : 0u, page_shift_) |
             (camera && beam ? MV_TRACE_MODE_BEAM : 0u);
    p.width = width;
    p.max_steps = step_limit(max_steps);
    p.proj = proj;
    if (cache_) {
      p.level_base[MV_TRACE_PAGE_STAMP] = cache_->stamp();
      dev_.dispatch(k, groups, local,
                    {camera ? camera : rays, &cache_->data(), &cache_->table(), &cache_->usage(),
                     &cache_->requests(), &results},
                    p);
      return;
    }
    dev_.dispatch(k, groups, local, {rays, camera, &words_, bricks, offsets, &results}, p);
  });
  dev_.barrier();
}

template <class P>
void TraceEngine::dispatch_pair(KernelId id, uint32_t items, const Buffer& a, const Buffer& b, P p) {
  Kernel& k = dev_.kernel(id);
  for_each_dispatch(0, items, [&](uint32_t first, uint32_t count, uint32_t groups, uint32_t local, uint32_t block) {
    p.first = first;
    p.count = count;
    p.block = block;
    dev_.dispatch(k, groups, local, {&a, &b}, p);
  });
  dev_.barrier();
}

// The coarse grid's full cells come from the trace itself: one ray per cell from its centre, with tmax 0 (it
// never leaves the cell it starts in) and a level of detail that stops it at the first full cell of the grid's
// side on its way down (te = 0, so s * 1 < 1.5 S holds from side S down), then packed into bits and dilated.
const Buffer& TraceEngine::beam_grid(uint32_t g) {
  auto found = beam_grids_.find(g);
  if (found != beam_grids_.end()) return found->second;
  const uint32_t n = g * g * g;
  const float side = 1.0f / static_cast<float>(g);
  std::vector<float> rays(uint64_t{n} * MV_RAY_FLOATS);
  for (uint32_t i = 0; i < n; ++i) {
    const MvRay r{(static_cast<float>(i % g) + 0.5f) * side, (static_cast<float>(i / g % g) + 0.5f) * side,
                  (static_cast<float>(i / g / g) + 0.5f) * side, 1.0f, 0.5f, 0.25f, 0.0f, 1.5f * side};
    std::copy_n(&r.ox, MV_RAY_FLOATS, rays.data() + uint64_t{i} * MV_RAY_FLOATS);
  }
  Buffer ray_buf = dev_.alloc(rays.size() * 4, "beam grid rays");
  dev_.upload(ray_buf, rays.data(), rays.size() * 4);
  Buffer counts = dev_.alloc(uint64_t{n} * 4, "beam grid cells");
  dev_.fill(counts, 0, uint64_t{n} * 4);
  trace(&ray_buf, nullptr, 0, n, 0, 1.0f, step_limit(4 * levels_ + 16), true, counts);
  const uint32_t full_words = g * g * mv_beam_row_words(g);
  const uint32_t marked_words = (g + 2) * (g + 2) * mv_beam_row_words(g + 2);
  Buffer full = dev_.alloc(uint64_t{full_words} * 4, "beam grid");
  Buffer marked = dev_.alloc(uint64_t{marked_words} * 4, "beam grid, dilated");
  MvBeamParams p{};
  p.cells = g;
  dispatch_pair(KernelId::beam_pack, full_words, counts, full, p);
  dispatch_pair(KernelId::beam_dilate, marked_words, full, marked, p);
  return beam_grids_.emplace(g, std::move(marked)).first->second;
}

void TraceEngine::beam(Buffer& camera, uint32_t width, uint32_t height, uint32_t cells, float reach,
                       uint32_t parent_cells, float parent_reach, float proj) {
  auto check = [&](uint32_t g, float r) {
    if (g < 4 || g > kBeamMaxCells || (g & (g - 1)) != 0 || levels_ < 2 || g > (uint32_t{1} << levels_) || !(r > 0))
      throw Error("trace: a beam grid of " + std::to_string(g) + " cells per axis");
  };
  check(cells, reach);
  if (parent_cells) check(parent_cells, parent_reach);
  const uint32_t tiles = mv_beam_tile_count(width, height, MV_BEAM_TILE);
  // each pass over its tiles: the parent's starts after the tiles' (beam_camera_floats)
  auto pass = [&](uint32_t g, float r, uint32_t tile, uint32_t at, uint32_t parent_at) {
    const Buffer& marked = beam_grid(g);
    MvBeamParams p{};
    p.cells = g;
    p.width = width;
    p.height = height;
    p.reach = r;
    p.lod_limit = proj > 0 ? 2 * proj / static_cast<float>(g) : 1e30f;
    p.tile = tile;
    p.at = at;
    p.parent_at = parent_at;
    dispatch_pair(KernelId::beam_starts, mv_beam_tile_count(width, height, tile), marked, camera, p);
  };
  if (parent_cells) pass(parent_cells, parent_reach, 2 * MV_BEAM_TILE, tiles, MV_BEAM_NO_PARENT);
  pass(cells, reach, MV_BEAM_TILE, 0, parent_cells ? tiles : MV_BEAM_NO_PARENT);
}

uint32_t TraceEngine::list_secondary(const Buffer& hits, uint32_t count, Buffer& listed) {
  Buffer flags = dev_.alloc(uint64_t{std::max(count, 1u)} * 4, "secondary ray flags");
  dispatch_pair(KernelId::secondary_flags, count, hits, flags, MvSecondaryParams{});
  return static_cast<uint32_t>(select_flagged(dev_, flags, listed, count));
}

void TraceEngine::secondary(const Buffer* rays, const Buffer* camera, const Buffer& hits, const Buffer& listed,
                            const Buffer* table, uint32_t first_ray, uint32_t count, MvSecondaryParams p, Buffer& out) {
  Kernel& k = dev_.kernel(KernelId::secondary_rays);
  p.levels = levels_;
  p.camera = camera ? 1u : 0u;
  for_each_dispatch(first_ray, count, [&](uint32_t first, uint32_t n, uint32_t groups, uint32_t local, uint32_t block) {
    p.first = first;
    p.count = n;
    p.block = block;
    dev_.dispatch(k, groups, local, {rays, camera, &hits, &listed, table, &out}, p);
  });
  dev_.barrier();
}

void TraceEngine::attach_colours(const EncodedDag& dag, const std::vector<uint8_t>& rgb, const ColourPalette* palette) {
  if (cache_) throw Error("trace: colours are traced on resident DAGs only");
  const std::vector<uint32_t> meta = trace_colour_meta(dag);
  const uint64_t root = meta.size() > MV_COLOUR_SIZES_AT(levels_) ? meta[MV_COLOUR_SIZES_AT(levels_)] : 0;
  if (rgb.size() % 3 != 0 || rgb.size() / 3 != root)
    throw Error("trace: " + std::to_string(rgb.size() / 3) + " colours for a DAG of " + std::to_string(root) +
                " octree nodes");
  const std::vector<uint32_t> words = trace_colour_words(rgb, palette);
  colour_meta_ = dev_.alloc(meta.size() * 4, "hit colour sizes");
  dev_.upload(colour_meta_, meta.data(), meta.size() * 4);
  colours_ = dev_.alloc(std::max<size_t>(words.size(), 1) * 4, "voxel colours");
  if (!words.empty()) dev_.upload(colours_, words.data(), words.size() * 4);
}

void TraceEngine::hit_colours(const Buffer& hits, uint32_t first_hit, uint32_t count, Buffer& out) {
  if (!has_colours()) throw Error("trace: the DAG has no colours");
  const bool ssvdag = encoding_ == static_cast<uint32_t>(Encoding::ssvdag);
  Kernel& k = dev_.kernel(ssvdag ? KernelId::hit_colours_ssvdag : KernelId::hit_colours);
  const Buffer* bricks = ssvdag ? &bricks_ : &words_;
  for_each_dispatch(first_hit, count, [&](uint32_t first, uint32_t n, uint32_t groups, uint32_t local, uint32_t) {
    MvTraceParams p = params_;
    p.first = first;
    p.count = n;
    p.mode = MV_TRACE_MODE(levels_, 0u, 0u, 0u);
    dev_.dispatch(k, groups, local, {&hits, &words_, bricks, &colour_meta_, &colours_, &out}, p);
  });
  dev_.barrier();
}

void TraceEngine::hit_entries(const Buffer& hits, uint32_t first_hit, uint32_t count, Buffer& out) {
  if (!cache_ || cache_->config().plane_words == 0) throw Error("trace: colour entries need a paged DAG with its size plane");
  const bool ssvdag = encoding_ == static_cast<uint32_t>(Encoding::ssvdag);
  Kernel& k = dev_.kernel(ssvdag ? KernelId::hit_entries_paged_ssvdag : KernelId::hit_entries_paged);
  for_each_dispatch(first_hit, count, [&](uint32_t first, uint32_t n, uint32_t groups, uint32_t local, uint32_t) {
    MvTraceParams p = params_;
    p.first = first;
    p.count = n;
    p.mode = MV_TRACE_MODE(levels_, 0u, 0u, page_shift_);
    dev_.dispatch(k, groups, local, {&hits, &cache_->data(), &cache_->table(), &cache_->plane(), &out}, p);
  });
  dev_.barrier();
}

// ---- the public ray-query interface ----

Tracer::Tracer(Device& dev, const MvxFile& file, bool colours)
    : grid_(file.grid), engine_(std::make_unique<TraceEngine>(dev, file.dag)) {
  if (colours && !file.colours.empty()) engine_->attach_colours(file.dag, file.colours, file.colour_palette.get());
}

bool Tracer::has_colours() const {
  return cache_ ? cache_->config().plane_words != 0 : engine_->has_colours();
}

void Tracer::hit_colours(const Buffer& hits, uint32_t count, Buffer& scratch, uint32_t* out) {
  if (count == 0) return;
  if (!cache_) {
    engine_->hit_colours(hits, 0, count, scratch);
    engine_->device().download(scratch, out, uint64_t{count} * 4);
    return;
  }
  engine_->hit_entries(hits, 0, count, scratch);
  engine_->device().download(scratch, out, uint64_t{count} * 4);
  for (uint32_t i = 0; i < count; ++i) out[i] = out[i] == MV_NO_ENTRY ? 0u : paged_.colour(out[i]) | MV_COLOUR_ALPHA;
}

void Tracer::read_page(uint32_t page, std::span<uint32_t> words) const {
  const uint32_t pw = paged_.page_words;
  paged_.read(page, words.first(pw));
  if (words.size() > pw) paged_.read_sizes(page, words.subspan(pw));
}

Tracer::Tracer(Device& dev, PagedDag dag, uint64_t cache_bytes, bool preload)
    : grid_(dag.grid), paged_(std::move(dag)) {
  if (paged_.pages == 0 || paged_.page_words == 0 || !paged_.read) throw Error("trace: the paged DAG has no pages");
  const uint64_t page_bytes = uint64_t{paged_.page_words} * 4;
  if (cache_bytes < page_bytes)
    throw Error("trace: a page cache of " + std::to_string(cache_bytes) + " bytes holds no page of " +
                std::to_string(page_bytes) + " bytes");
  PageCacheConfig c;
  c.page_words = paged_.page_words;
  c.pages = paged_.pages;
  // the size plane, when the DAG's colours can be found through the cache (paging/paged_sizes.h): a slot holds a
  // page and its plane, both inside cache_bytes
  const bool plane = paged_.plane_words != 0 && paged_.read_sizes && paged_.colour;
  const uint64_t slot_bytes = page_bytes + (plane ? uint64_t{paged_.plane_words} * 4 : 0);
  if (cache_bytes < slot_bytes)
    throw Error("trace: a page cache of " + std::to_string(cache_bytes) + " bytes holds no page of " +
                std::to_string(slot_bytes) + " bytes with its size plane");
  // more slots than pages would never be used
  c.slots = static_cast<uint32_t>(std::min<uint64_t>(cache_bytes / slot_bytes, paged_.pages));
  // where each level starts (64-bit: the walk adds offsets to a virtual address); a word stream with absolute
  // pointers has none, and its levels start at 0
  const bool ssvdag = paged_.encoding == Encoding::ssvdag;
  if (ssvdag && paged_.level_starts.size() != paged_.levels + 1u) throw Error("trace: the paged ssvdag has no level starts");
  if (!ssvdag && !paged_.level_starts.empty() && paged_.level_starts.size() != paged_.levels + 1u)
    throw Error("trace: " + std::to_string(paged_.level_starts.size()) + " level starts for " +
                std::to_string(paged_.levels) + " levels");
  for (uint32_t l = 0; l <= paged_.levels; ++l) {
    const uint64_t s = paged_.level_starts.empty() ? 0 : paged_.level_starts[l];
    if (s >= uint64_t{paged_.pages} * paged_.page_words * (ssvdag ? 2 : 1)) throw Error("trace: a paged level starts past its pages");
    c.table_tail.push_back(static_cast<uint32_t>(s));
    c.table_tail.push_back(static_cast<uint32_t>(s >> 32));
  }
  if (plane) c.plane_words = paged_.plane_words;
  cache_ = std::make_unique<PageCache>(dev, c);
  engine_ = std::make_unique<TraceEngine>(dev, paged_.encoding, paged_.levels, *cache_);
  if (preload && c.slots == c.pages) {
    // the whole DAG fits: load it now, in page order, so the table maps it as one run; nothing can be evicted
    // from here on, so the traversal stops stamping usage (a failed page is requested again like any other)
    preloaded_ = cache_->preload([&](uint32_t page, std::span<uint32_t> words) {
      read_page(page, words);
      return true;
    });
    engine_->set_usage_stamps(false);
  }
}

Tracer::~Tracer() = default;

void Tracer::begin_pass() {
  if (cache_) cache_->begin_pass();
}

void Tracer::read_ahead() {
  if (!cache_) return;
  if (ahead_.valid()) ahead_.get();  // one read-ahead per pass: the last one's pages go unused
  std::vector<uint32_t> pages = cache_->missing_so_far(cache_->config().slots);
  if (pages.empty()) return;
  ahead_ = std::async(std::launch::async, [this, pages = std::move(pages)]() mutable {
    const auto t0 = std::chrono::steady_clock::now();
    const uint32_t words = paged_.page_words + cache_->config().plane_words;
    PagesRead r;
    r.pages = std::move(pages);
    r.words.resize(uint64_t{words} * r.pages.size());
    r.ok.assign(r.pages.size(), 0);
    for (size_t i = 0; i < r.pages.size(); ++i) {
      try {
        read_page(r.pages[i], std::span<uint32_t>(r.words.data() + i * words, words));
        r.ok[i] = 1;
      } catch (const std::exception&) {
        // left to the update, which reads the page again and reports why it fails
      }
    }
    r.seconds = seconds_since(t0);
    return r;
  });
}

CacheUpdateStats Tracer::end_pass() {
  if (!cache_) return {};
  const PagesRead ahead = ahead_.valid() ? ahead_.get() : PagesRead();
  std::atomic<uint32_t> from_ahead{0};
  CacheUpdateStats st = cache_->update([&](uint32_t page, std::span<uint32_t> words) {
    const auto at = std::lower_bound(ahead.pages.begin(), ahead.pages.end(), page);
    const size_t i = static_cast<size_t>(at - ahead.pages.begin());
    if (at != ahead.pages.end() && *at == page && ahead.ok[i]) {
      std::copy_n(ahead.words.begin() + static_cast<std::ptrdiff_t>(i * words.size()), words.size(), words.begin());
      from_ahead.fetch_add(1, std::memory_order_relaxed);
    } else {
      read_page(page, words);
    }
    return true;
  });
  st.read_ahead = from_ahead.load();
  st.read_ahead_seconds = ahead.seconds;
  passes_.push_back(st);
  return st;
}

std::vector<RayHit> Tracer::trace(const std::vector<Ray>& rays, const TraceOptions& options,
                                  std::vector<uint32_t>* colours) {
  std::vector<RayHit> out(rays.size());
  if (colours) colours->clear();
  if (rays.empty()) return out;
  if (rays.size() > UINT32_MAX / MV_HIT_WORDS) throw Error("trace: too many rays in one batch");
  // World to the root cube [0, 1)^3: a translation and one scale, so t keeps its meaning.
  const double side = grid_.voxel_size * grid_.resolution;
  const uint32_t n = static_cast<uint32_t>(rays.size());
  std::vector<uint32_t> cube(uint64_t{n} * MV_RAY_FLOATS);
  for (uint32_t i = 0; i < n; ++i) {
    const Ray& r = rays[i];
    float c[6];
    for (int a = 0; a < 3; ++a) {
      if (!std::isfinite(r.origin[a]) || !std::isfinite(r.direction[a]))
        throw Error("trace: ray " + std::to_string(i) + " has a non-finite origin or direction");
      c[a] = static_cast<float>((double(r.origin[a]) - grid_.origin[a]) / side);
      c[3 + a] = static_cast<float>(double(r.direction[a]) / side);
    }
    if (std::isnan(r.tmax)) throw Error("trace: ray " + std::to_string(i) + " has a NaN tmax");
    mv_store_ray(cube.data(), i, MvRay{c[0], c[1], c[2], c[3], c[4], c[5], std::min(r.tmax, 1e30f), 0.0f});
  }
  Device& dev = engine_->device();
  Buffer ray_buf = dev.alloc(cube.size() * 4, "rays");
  dev.upload(ray_buf, cube.data(), cube.size() * 4);
  Buffer hit_buf = dev.alloc(uint64_t{n} * MV_HIT_WORDS * 4, "ray hits");
  passes_.clear();
  for (uint32_t pass = 1;; ++pass) {
    begin_pass();
    engine_->trace(&ray_buf, nullptr, 0, n, 0, 0.0f, options.max_steps, false, hit_buf);
    if (!cache_) break;
    const CacheUpdateStats st = end_pass();
    if (st.requested == 0 || st.loaded == 0 || pass == options.max_passes) break;  // done, stuck, or enough
  }
  std::vector<uint32_t> words(uint64_t{n} * MV_HIT_WORDS);
  dev.download(hit_buf, words.data(), words.size() * 4);
  if (colours && has_colours()) {
    Buffer colour_buf = dev.alloc(uint64_t{n} * 4, "hit colours");
    colours->resize(n);
    hit_colours(hit_buf, n, colour_buf, colours->data());
  }
  for (uint32_t i = 0; i < n; ++i) {
    const MvHit w = mv_load_hit(words.data(), i);
    RayHit& h = out[i];
    h.hit = MV_INFO_STATUS(w.info) == MV_TRACE_HIT;
    h.gave_up = MV_INFO_STATUS(w.info) == MV_TRACE_GAVE_UP;
    h.steps = w.steps;
    if (!h.hit) continue;
    h.coarse = MV_INFO_COARSE(w.info) != 0;
    h.t = w.t;
    h.level = MV_INFO_LEVEL(w.info);
    h.cell[0] = w.x;
    h.cell[1] = w.y;
    h.cell[2] = w.z;
    uint32_t axis = MV_INFO_AXIS(w.info);
    if (axis != MV_AXIS_NONE) h.normal[axis] = MV_INFO_NEGATIVE(w.info) ? -1 : 1;
  }
  return out;
}

}  // namespace mv
