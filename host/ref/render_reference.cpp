// The CPU reference renderer: the same rays and shading as render(), traced by the flat voxel DDA.
#include <tbb/parallel_for.h>

#include "megavox/render.h"
#include "colour_reference.h"
#include "trace_reference.h"
#include "trace/host_trace.h"
#include "render/frame.h"

namespace mv {

RenderResult render_reference(const MvxFile& file, const Camera& camera, const RenderOptions& options) {
  const FrameSetup s = frame_setup(file.grid, file.dag.levels, camera, options);
  const uint32_t n = s.width * s.height;
  ref::Occupancy occ(decode_encoded(file.dag), file.dag.levels);
  // Heat maps count the hierarchical walk's steps, which the flat DDA does not take: for them the primary
  // rays run through the kernel's own traversal code compiled for the host.
  HostTracer host(file.dag);
  FrameResults res;
  res.hits.resize(uint64_t{n} * MV_HIT_WORDS);
  std::vector<MvRay> primary(n);
  std::vector<MvHit> first(n);
  tbb::parallel_for(0u, n, [&](uint32_t i) {
    primary[i] = mv_camera_ray(s.camera, i, s.width);
    first[i] = options.shading == Shading::heat ? host.trace(primary[i], s.proj, options.max_steps)
                                                : ref::trace(occ, primary[i], s.proj);
    mv_store_hit(res.hits.data(), i, first[i]);
  });
  RenderResult out;
  for (const MvHit& h : first) out.hits += MV_INFO_STATUS(h.info) == MV_TRACE_HIT;
  if (frame_uses_colours(options) && !file.colours.empty()) {
    const ref::NodeColours colours(decode_encoded(file.dag), file.dag.levels, file.colours);
    res.colours.resize(n);
    for (uint32_t i = 0; i < n; ++i)
      res.colours[i] = MV_INFO_STATUS(first[i].info) != MV_TRACE_HIT
                           ? 0
                           : colours.at(MV_INFO_LEVEL(first[i].info), first[i].x, first[i].y, first[i].z);
  }
  if (options.shading == Shading::shaded) {
    res.shadow.assign(n, 0);
    res.ao.assign(n, 0);
    tbb::parallel_for(0u, n, [&](uint32_t i) {
      auto occluded = [&](const MvSecondaryParams& p) {
        MvRay r = mv_make_secondary(primary[i], first[i], s.ao_table.data(), i, p);
        return MV_INFO_STATUS(ref::trace(occ, r, s.proj).info) == MV_TRACE_HIT ? 1u : 0u;
      };
      MvSecondaryParams shadow = s.shadow;
      shadow.levels = s.levels;
      res.shadow[i] = occluded(shadow);
      for (uint32_t k = 0; k < s.ao_samples; ++k) {
        MvSecondaryParams p = s.ao;
        p.levels = s.levels;
        p.sample_k = k;
        res.ao[i] += occluded(p);
      }
    });
  }
  out.image = shade(s, options, res);
  return out;
}

}  // namespace mv
