#include "attributes_bench.h"

#include <algorithm>
#include <limits>

#include "peak_rss.h"
#include "scratch_dir.h"
#include "megavox/mvx.h"
#include "megavox/trace.h"

namespace mv::bench {

namespace {

// A build's stages without reading the input and writing the file (the palette's selection is part of the write).
double stage_seconds(const BuildReport& r) {
  double s = 0;
  for (const BuildReport::Stage& st : r.seconds)
    if (st.name != "read" && st.name != "write") s += st.seconds;
  return s;
}

AttributeBuild best_build(Device& dev, const BuildOptions& base, uint32_t bits, uint32_t repeats, bool& reset) {
  AttributeBuild b;
  b.bits = bits;
  BuildOptions o = base;
  o.attributes = bits ? Attributes::rgb : Attributes::none;
  o.colour_bits = bits ? bits : 24;
  reset = reset_peak_rss() && reset;
  b.stage_seconds = std::numeric_limits<double>::infinity();
  for (uint32_t k = 0; k < repeats; ++k) {
    BuildReport r = build_mvx(dev, o);
    const double s = stage_seconds(r);
    if (s < b.stage_seconds) b.stage_seconds = s, b.report = std::move(r);
  }
  b.peak_rss_bytes = peak_rss_bytes();
  const BuildReport& r = b.report;
  b.colour_bytes = r.colour_bytes;
  b.colour_bits_per_voxel = r.colour_bits_per_voxel;
  if (r.voxels) b.raw_bits_per_voxel = 8.0 * double(32 + 3 * r.colour_entries) / double(r.voxels);
  if (r.colour_entries) b.compression_rate = double(r.colour_bytes) / double(3 * r.colour_entries);
  return b;
}

}  // namespace

AttributesBenchResult bench_attributes(Device& dev, const std::string& cloud, const AttributesBenchOptions& opt) {
  AttributesBenchResult out;
  out.input = cloud;
  out.peak_rss_reset = true;
  const ScratchDir scratch;
  BuildOptions base;
  base.input = cloud;
  base.resolution = opt.resolution;
  base.placement = parse_grid_origin("min");
  base.output = scratch.file("warm.mvx");
  base.attributes = Attributes::rgb;
  build_mvx(dev, base);  // compiles the kernels of both paths
  base.output = scratch.file("grey.mvx");
  out.colourless = best_build(dev, base, 0, opt.repeats, out.peak_rss_reset);
  out.points = out.colourless.report.points;
  out.triangles = out.colourless.report.triangles;
  out.voxels = out.colourless.report.voxels;
  std::string lossless;
  for (uint32_t bits : opt.bits) {
    base.output = scratch.file("c" + std::to_string(bits) + ".mvx");
    if (bits == 24) lossless = base.output;
    out.coloured.push_back(best_build(dev, base, bits, opt.repeats, out.peak_rss_reset));
    out.entries = out.coloured.back().report.colour_entries;
  }
  if (lossless.empty()) return out;

  const MvxFile file = read_mvx(lossless);
  const Camera cam = view_camera(file.bounds, "iso");
  RenderOptions ro = opt.render;
  ro.shading = Shading::shaded;
  auto best_render = [&](Tracer& tracer, double* colour_pass) {
    RenderResult best;
    double seconds = std::numeric_limits<double>::infinity();
    for (uint32_t k = 0; k < std::max<uint32_t>(opt.repeats, 1) + 1; ++k) {  // the first compiles
      RenderResult r = render(tracer, cam, ro);
      if (k > 0 && r.trace_seconds < seconds) seconds = r.trace_seconds, best = std::move(r);
    }
    if (colour_pass)
      for (const RenderPass& p : best.passes)
        if (p.name == "colour") *colour_pass += p.seconds;
    return std::make_pair(seconds, std::move(best));
  };
  Tracer coloured(dev, file), grey(dev, file, false);
  auto [cs, c] = best_render(coloured, &out.colour_pass_seconds);
  auto [gs, g] = best_render(grey, nullptr);
  out.render_seconds = cs;
  out.grey_render_seconds = gs;
  out.hits = c.hits;
  for (size_t i = 0; i + 2 < c.image.rgb.size() && i + 2 < g.image.rgb.size(); i += 3)
    out.pixels_changed += c.image.rgb[i] != g.image.rgb[i] || c.image.rgb[i + 1] != g.image.rgb[i + 1] ||
                          c.image.rgb[i + 2] != g.image.rgb[i + 2];
  return out;
}

}  // namespace mv::bench
