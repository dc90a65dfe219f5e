#include <algorithm>

#include "megavox/device.h"
#include "megavox/error.h"
#include "megavox/point_render.h"
#include "point_frame.h"

namespace mv {

PointRenderResult render_points(Device& dev, const PointHierarchy& h, const PointRenderOptions& options) {
  points::SplatFrame f = points::splat_frame(h, options);
  const uint64_t pixels = uint64_t{f.params.width} * f.params.height;
  const uint64_t n = f.cells.size() / 3;
  Buffer depth = dev.alloc(pixels * 4, "splat depth");
  Buffer index = dev.alloc(pixels * 4, "splat winners");
  dev.fill(depth, MV_SPLAT_EMPTY, pixels * 4);
  dev.fill(index, MV_SPLAT_EMPTY, pixels * 4);
  dev.barrier();
  // Points go up in chunks the device holds; one work-item per point keeps every loop within a loop cap.
  const uint64_t chunk = std::max<uint64_t>(1, std::min<uint64_t>(n, uint64_t{1} << 22));
  Buffer cells = dev.alloc(std::max<uint64_t>(1, chunk) * 12, "splat points");
  const uint32_t local = 64;
  for (int pass = 0; pass < 2; ++pass) {
    Kernel& k = dev.kernel(pass == 0 ? KernelId::splat_depth : KernelId::splat_index);
    for (uint64_t first = 0; first < n; first += chunk) {
      const uint64_t m = std::min(chunk, n - first);
      dev.upload(cells, f.cells.data() + 3 * first, m * 12);
      MvSplatParams p = f.params;
      p.n = static_cast<uint32_t>(m);
      p.base = static_cast<uint32_t>(first);
      const uint32_t groups = static_cast<uint32_t>(std::min<uint64_t>((m + local - 1) / local, dev.info().max_groups));
      dev.dispatch(k, groups, local, {&cells, &depth, &index}, p);
      dev.barrier();
    }
  }
  std::vector<uint32_t> d(pixels), w(pixels);
  dev.download(depth, d.data(), pixels * 4);
  dev.download(index, w.data(), pixels * 4);
  PointRenderResult r;
  r.image = points::resolve_frame(f, d, w, &r.pixels_covered);
  r.depth = std::move(d);
  r.winner = std::move(w);
  r.nodes_drawn = f.nodes.size();
  r.points_drawn = n;
  return r;
}

}  // namespace mv
