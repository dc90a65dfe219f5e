// `megavox bench trace` (see trace_bench.h).
#include "trace_bench.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>

#include "baselines.h"
#include "io/mesh_source.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "megavox/render.h"
#include "megavox/trace.h"
#include "trace_reference.h"
#include "render/frame.h"
#include "trace/host_trace.h"

#include "stopwatch.h"

namespace mv::bench {

namespace {


// Mrays/s of a CPU tracer over every `every`-th primary ray of the image, on all threads. The hits are
// folded into a checksum so the work cannot be optimized away.
template <class Trace>
double cpu_rate(const FrameSetup& s, uint32_t every, Trace&& trace) {
  const uint32_t n = s.width * s.height;
  auto t0 = Clock::now();
  std::atomic<uint64_t> checksum{0};
  uint64_t rays = tbb::parallel_reduce(
      tbb::blocked_range<uint32_t>(0, n, 1024), uint64_t{0},
      [&](const tbb::blocked_range<uint32_t>& r, uint64_t acc) {
        uint64_t sum = 0;
        for (uint32_t i = r.begin(); i < r.end(); ++i)
          if (i % every == 0) {
            MvHit h = trace(mv_camera_ray(s.camera, i, s.width));
            sum += MV_FBITS(h.t) + h.info + h.x;
            ++acc;
          }
        checksum += sum;
        return acc;
      },
      std::plus<>());
  volatile uint64_t keep = checksum.load();
  (void)keep;
  return double(rays) / since(t0) / 1e6;
}

// Embree over the source triangles with the kernel's primary rays (world units). Returns per-pixel hit flags.
std::vector<uint8_t> embree_trace(const std::string& mesh, const Camera& cam, const FrameSetup& s,
                                  uint32_t repeats, TraceBenchResult& out) {
  auto src = io::open_mesh(mesh);
  std::vector<uint32_t> indices, batch;
  while (src->next_triangles(batch, 1 << 20)) indices.insert(indices.end(), batch.begin(), batch.end());
  out.triangles = indices.size() / 3;
  baseline::EmbreeFrame f;
  f.width = s.width;
  f.height = s.height;
  for (int a = 0; a < 3; ++a) {
    f.eye[a] = float(cam.eye[a]);
    f.dir0[a] = s.camera[MV_CAMERA_BASE + a];
    f.dx[a] = s.camera[MV_CAMERA_DU + a];
    f.dy[a] = s.camera[MV_CAMERA_DV + a];
  }
  baseline::EmbreeResult e = baseline::embree_primary_hits(src->positions(), indices, f, repeats);
  out.have_embree = true;
  out.embree_build_seconds = e.build_seconds;
  out.embree_seconds = e.trace_seconds;
  out.embree_mrays = double(f.width) * f.height / e.trace_seconds / 1e6;
  out.embree16_mrays = double(f.width) * f.height / e.packet_seconds / 1e6;
  out.embree16_mismatches = e.packet_mismatches;
  for (uint8_t h : e.hit) out.embree_hits += h;
  return std::move(e.hit);
}

// Steps (cells visited: descents and moves) per ray of the kernel's host build over the whole frame: primary
// rays, and for each primary hit its shadow ray and its AO rays, made as the renderer makes them.
StepsPerRay steps_per_ray(const FrameSetup& s, HostTracer& host, uint32_t max_steps) {
  const uint32_t n = s.width * s.height;
  struct Sums {
    uint64_t primary = 0, hits = 0, shadow = 0, ao = 0, ao_rays = 0, hit_steps = 0;
  };
  Sums z = tbb::parallel_reduce(
      tbb::blocked_range<uint32_t>(0, n, 4096), Sums{},
      [&](const tbb::blocked_range<uint32_t>& r, Sums acc) {
        for (uint32_t i = r.begin(); i < r.end(); ++i) {
          const MvRay pr = mv_camera_ray(s.camera, i, s.width);
          const MvHit h = host.trace(pr, s.proj, max_steps);
          acc.primary += h.steps;
          if (MV_INFO_STATUS(h.info) != MV_TRACE_HIT) continue;
          ++acc.hits;
          acc.hit_steps += h.steps;
          MvSecondaryParams sp = s.shadow;
          sp.levels = s.levels;
          acc.shadow += host.trace(mv_make_secondary(pr, h, nullptr, i, sp), s.proj, max_steps).steps;
          for (uint32_t k = 0; k < s.ao_samples; ++k) {
            MvSecondaryParams p = s.ao;
            p.levels = s.levels;
            p.sample_k = k;
            acc.ao += host.trace(mv_make_secondary(pr, h, s.ao_table.data(), i, p), s.proj, max_steps).steps;
            ++acc.ao_rays;
          }
        }
        return acc;
      },
      [](Sums a, const Sums& b) {
        a.primary += b.primary, a.hits += b.hits, a.shadow += b.shadow, a.ao += b.ao, a.ao_rays += b.ao_rays;
        a.hit_steps += b.hit_steps;
        return a;
      });
  StepsPerRay out;
  out.primary = n ? double(z.primary) / n : 0;
  out.primary_hit = z.hits ? double(z.hit_steps) / double(z.hits) : 0;
  out.shadow = z.hits ? double(z.shadow) / double(z.hits) : 0;
  out.ao = z.ao_rays ? double(z.ao) / double(z.ao_rays) : 0;
  return out;
}

}  // namespace

constexpr uint64_t kReferenceVoxels = uint64_t{64} << 20;

TraceBenchResult run_trace_bench(Device& dev, const std::vector<std::string>& files, const std::string& mesh,
                                 const TraceBenchOptions& o) {
  if (files.empty()) throw Error("bench trace: name at least one .mvx file");
  if (o.repeats == 0) throw Error("bench trace: --repeats must be at least 1");
  TraceBenchResult out;
  out.mesh = mesh;
  out.device = dev.info().name;
  out.width = o.width;
  out.height = o.height;
  out.lod_pixels = o.lod_pixels;
  RenderOptions ro;
  ro.width = o.width;
  ro.height = o.height;
  ro.lod_pixels = o.lod_pixels;
  ro.ao_samples = o.ao_samples;
  // All files open at once and the repeats alternate between them, so drift on a noisy machine hits every
  // encoding alike; the camera frames the first file, so all trace the same rays.
  std::vector<MvxFile> mvx;
  std::vector<std::unique_ptr<Tracer>> tracers;
  for (const std::string& f : files) {
    mvx.push_back(read_mvx(f));
    if (o.cache_bytes)
      tracers.push_back(std::make_unique<Tracer>(dev, open_paged_mvx(f), o.cache_bytes));
    else
      tracers.push_back(std::make_unique<Tracer>(dev, mvx.back()));
  }
  const Camera cam = o.use_camera ? o.camera : view_camera(mvx.front().bounds, o.view);
  out.encodings.resize(files.size());
  for (size_t f = 0; f < files.size(); ++f) {
    TraceBenchEncoding& e = out.encodings[f];
    e.file = files[f];
    e.format = encoding_name(mvx[f].dag.encoding);
    e.resolution = mvx[f].grid.resolution;
    e.primary_seconds = e.shadow_seconds = e.ao_seconds = INFINITY;
  }
  std::vector<std::vector<double>> render_seconds(files.size());  // [file][repeat]: all passes
  for (uint32_t rep = 0; rep < o.repeats; ++rep)
    for (size_t f = 0; f < files.size(); ++f) {
      TraceBenchEncoding& e = out.encodings[f];
      {  // the beam pre-pass's lever, measured in the same run
        RenderOptions off = ro;
        off.beam = false;
        off.shading = Shading::depth;
        RenderResult r = render(*tracers[f], cam, off);
        for (const RenderPass& p : r.passes)
          if (p.name == "primary")
            e.primary_mrays_no_beam = std::max(e.primary_mrays_no_beam, double(p.rays) / p.seconds / 1e6);
      }
      RenderResult r = render(*tracers[f], cam, ro);
      e.hits = r.hits;
      e.beam_steps = double(r.primary_steps) / (double(ro.width) * ro.height);
      e.beam_hit_steps = r.hits ? double(r.hit_steps) / double(r.hits) : 0;
      e.paged = tracers[f]->paged();
      e.converged = e.converged && r.converged;
      double total = 0;
      for (const RenderPass& p : r.passes) total += p.seconds;
      render_seconds[f].push_back(total);
      // per kind of ray, this render's rays and seconds over its tiles (a paged render may trace in bands)
      for (const char* kind : {"primary", "shadow", "ao"}) {
        uint64_t rays = 0;
        double seconds = 0;
        for (const RenderPass& p : r.passes)
          if (p.name == kind) rays += p.rays, seconds += p.seconds;
        if (seconds <= 0) continue;
        const std::string k = kind;
        double& best = k == "primary" ? e.primary_seconds : k == "shadow" ? e.shadow_seconds : e.ao_seconds;
        if (seconds >= best) continue;
        best = seconds;
        (k == "primary" ? e.primary_mrays : k == "shadow" ? e.shadow_mrays : e.ao_mrays) = double(rays) / seconds / 1e6;
      }
    }
  std::vector<uint8_t> embree_hit;
  for (size_t f = 0; f < files.size(); ++f) {
    const MvxFile& file = mvx[f];
    TraceBenchEncoding& e = out.encodings[f];
    const FrameSetup s = frame_setup(file.grid, file.dag.levels, cam, ro);
    HostTracer host(file.dag);
    e.host_core_mrays = cpu_rate(s, 1, [&](const MvRay& r) { return host.trace(r, s.proj, ro.max_steps); });
    e.steps = steps_per_ray(s, host, ro.max_steps);
    // The flat reference holds every voxel in host maps: only for files it fits (0 = skipped).
    if (file.voxels <= kReferenceVoxels) {
      ref::Occupancy occ(decode_encoded(file.dag), file.dag.levels);
      e.reference_mrays = cpu_rate(s, 61, [&](const MvRay& r) { return ref::trace(occ, r, s.proj); });
    }
    if (!mesh.empty() && baseline::embree().built_in) {
      if (embree_hit.empty()) embree_hit = embree_trace(mesh, cam, s, o.repeats, out);
      // Silhouettes: the kernel's hit flags (its host build gives the same bytes) against Embree's.
      uint64_t agree = 0;
      const uint32_t n = s.width * s.height;
      for (uint32_t i = 0; i < n; ++i)
        agree += (MV_INFO_STATUS(host.trace(mv_camera_ray(s.camera, i, s.width), s.proj, ro.max_steps).info) ==
                  MV_TRACE_HIT) == (embree_hit[i] != 0);
      e.silhouette_agreement = double(agree) / n;
      e.over_embree = e.primary_mrays / out.embree_mrays;
    }
  }
  int sv = -1, ss = -1;
  for (size_t f = 0; f < files.size(); ++f) {
    if (out.encodings[f].format == "svdag" && sv < 0) sv = int(f);
    if (out.encodings[f].format == "ssvdag" && ss < 0) ss = int(f);
  }
  if (sv >= 0 && ss >= 0) {
    std::vector<double> ratios;
    for (uint32_t rep = 0; rep < o.repeats; ++rep) ratios.push_back(render_seconds[ss][rep] / render_seconds[sv][rep]);
    std::sort(ratios.begin(), ratios.end());
    out.ssvdag_over_svdag = ratios[ratios.size() / 2];
    out.ssvdag_over_svdag_primary = out.encodings[ss].primary_seconds / out.encodings[sv].primary_seconds;
  }
  return out;
}

}  // namespace mv::bench
