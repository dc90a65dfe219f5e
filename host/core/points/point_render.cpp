#include <algorithm>

#include <cstdio>
#include <memory>

#include "io/atomic_dir.h"
#include "primitives/chunking.h"
#include "megavox/device.h"
#include "megavox/point_build.h"
#include "megavox/error.h"
#include "megavox/point_render.h"
#include "point_frame.h"

namespace mv {

namespace {

PointRenderResult render_frame(Device& dev, const points::SplatFrame& f);

}  // namespace

PointRenderResult render_points(Device& dev, const PointHierarchy& h, const PointRenderOptions& options) {
  return render_frame(dev, points::splat_frame(h, options));
}

void render_during_build(Device& dev, const std::string& input, const std::string& dir, uint32_t frames,
                         const PointBuildOptions& build, const PointRenderOptions& render,
                         const std::function<void(const BuildFrame&)>& on_frame) {
  if (frames < 1 || frames > 10000) throw CodedError(ErrorCode::invalid_argument, "points render: the frame count must be 1-10000", setting_frames);
  PointCloudInfo info;
  PointColumns cloud = read_point_file(input, info);
  const points::FrameBox box = points::points_box(cloud);
  const uint64_t n = cloud.size();
  std::unique_ptr<points::LodRule> rule;  // made with the first frame, from the build's grid
  io::write_dir_atomically(dir, "frame_0000.png", [&](const std::string& tmp) {
    uint32_t frame = 0;
    auto emit = [&](const PointHierarchy& h, const std::vector<uint32_t>& roots, uint64_t made) {
      PointRenderResult r = render_frame(dev, points::splat_frame(h, render, roots, &box));
      char name[32];
      std::snprintf(name, sizeof name, "frame_%04u.png", frame);
      write_png(tmp + "/" + name, r.image);
      BuildFrame f;
      f.frame = frame++;
      f.nodes = made;
      f.front_nodes = r.nodes_drawn;
      f.points_drawn = r.points_drawn;
      f.path = dir + "/" + name;
      if (on_frame) on_frame(f);
    };
    PointBuildOptions o = build;
    o.checkpoint_points = std::max<uint64_t>(1, n / frames);
    o.prefix_points = std::max<uint64_t>(1, std::min(o.prefix_points, o.checkpoint_points / 4));
    o.front_fine_enough = [&](const PointHierarchy& grid, uint32_t level, uint64_t prefix) {
      if (!rule) rule = std::make_unique<points::LodRule>(grid, render, box);
      return rule->fine_enough(level, prefix);
    };
    o.on_checkpoint = [&](const PointHierarchy& h, const std::vector<uint32_t>& roots) {
      uint64_t made = 0;  // the front's partial counts the nodes made per level
      for (uint64_t c : h.nodes_per_level) made += c;
      if (frame + 1 < frames) emit(h, roots, made);
    };
    PointHierarchy h = build_point_hierarchy(dev, std::move(cloud), info, o);
    emit(h, {0}, h.nodes.size());
  });
}

namespace {

PointRenderResult render_frame(Device& dev, const points::SplatFrame& f) {
  const uint64_t pixels = uint64_t{f.params.width} * f.params.height;
  const uint64_t n = f.cells.size() / 3;
  Buffer depth = dev.alloc(pixels * 4, "splat depth");
  Buffer index = dev.alloc(pixels * 4, "splat winners");
  dev.fill(depth, MV_SPLAT_EMPTY, pixels * 4);
  dev.fill(index, MV_SPLAT_EMPTY, pixels * 4);
  dev.barrier();
  // Points go up in chunks the device holds; one work-item per point keeps every loop within a loop cap.
  const uint64_t chunk = std::max<uint64_t>(
      1, std::min<uint64_t>({n, uint64_t{1} << 22, detail::device_chunk(dev, "points render", 12, 12)}));
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

}  // namespace

}  // namespace mv
