#include "mask_bench.h"

#include <algorithm>
#include <filesystem>

#include "baselines.h"
#include "io/image_reader.h"
#include "mask/grabcut.h"
#include "mask/mask_score.h"
#include "megavox/error.h"
#include "megavox/mask.h"
#include "megavox/min_cut.h"
#include "min_cut_reference.h"
#include "stopwatch.h"

namespace fs = std::filesystem;

namespace mv::bench {

namespace {

std::vector<std::string> image_names(const std::string& data) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(fs::path(data) / "images", ec))
    if (e.is_regular_file()) names.push_back(e.path().stem().string());
  if (ec || names.empty()) throw Error("bench mask: no images in '" + data + "/images' (the GrabCut database)");
  std::sort(names.begin(), names.end());
  return names;
}

RasterImage upscale2(const RasterImage& img) {
  RasterImage out{img.width * 2, img.height * 2, img.channels, img.max_value, {}};
  out.samples.resize(size_t{out.width} * out.height * img.channels);
  for (uint32_t y = 0; y < out.height; ++y)
    for (uint32_t x = 0; x < out.width; ++x)
      for (uint32_t c = 0; c < img.channels; ++c)
        out.samples[(size_t{y} * out.width + x) * img.channels + c] =
            img.samples[(size_t{y / 2} * img.width + x / 2) * img.channels + c];
  return out;
}

std::vector<uint16_t> upscale2(const std::vector<uint16_t>& t, uint32_t w, uint32_t h) {
  std::vector<uint16_t> out(size_t{w} * h * 4);
  for (uint32_t y = 0; y < 2 * h; ++y)
    for (uint32_t x = 0; x < 2 * w; ++x) out[size_t{y} * 2 * w + x] = t[size_t{y / 2} * w + x / 2];
  return out;
}

// GrabCut's first graph from the database box (captured from the first cut, which BK makes).
GridGraph first_graph(Device& dev, const RasterImage& img, const std::vector<uint16_t>& truth) {
  const MaskBox box = mask::box_from_truth(truth, img.width, img.height);
  GridGraph g;
  mask::GrabCutOptions o;
  o.iterations = 1;
  mask::grabcut(dev, img, mask::box_labels(img.width, img.height, box.x, box.y, box.w, box.h), o, [&](const GridGraph& graph) {
    g = graph;
    MinCut c;
    c.source_side.assign(size_t{graph.width} * graph.height, 0);
    return c;
  });
  return g;
}

GridGraph four_connected(const GridGraph& g) {
  GridGraph f = g;
  f.connectivity = 4;
  f.edges.resize(size_t{g.width} * g.height * 4);
  for (size_t i = 0; i < size_t{g.width} * g.height; ++i)
    for (uint32_t d = 0; d < 4; ++d) f.edges[i * 4 + d] = g.edges[i * 8 + d];
  return f;
}

}  // namespace

std::vector<CutRun> bench_cuts(Device& dev, const std::string& data, uint32_t cut_images, MinCutSolver solver,
                               Parallelism* parallelism) {
  ParallelismMeter meter(dev);
  MinCutOptions options;
  options.solver = solver;
  std::vector<CutRun> runs;
  const auto names = image_names(data);
  for (uint32_t k = 0; k < std::min<size_t>(cut_images, names.size()); ++k) {
    const RasterImage img = io::read_image((fs::path(data) / "images" / (names[k] + ".ppm")).string());
    const RasterImage truth = io::read_image((fs::path(data) / "masks" / (names[k] + ".pgm")).string());
    for (int scale : {1, 2}) {
      const RasterImage im = scale == 1 ? img : upscale2(img);
      const std::vector<uint16_t> tr = scale == 1 ? truth.samples : upscale2(truth.samples, truth.width, truth.height);
      const GridGraph g8 = first_graph(dev, im, tr);
      for (uint32_t conn : {4u, 8u}) {
        const GridGraph g = conn == 8 ? g8 : four_connected(g8);
        CutRun r{names[k], g.width, g.height, conn};
        const MinCut want = ref::bk_min_cut(g, &r.bk_seconds);
        min_cut(dev, g, options);  // warm: kernels built, memory pooled
        if (parallelism) meter.start();
        const auto t0 = Clock::now();
        const MinCut got = min_cut(dev, g, options);
        r.megavox_seconds = since(t0);
        if (parallelism) accumulate(*parallelism, meter.stop());
        r.value = got.value;
        r.same_cut = got.value == want.value && got.source_side == want.source_side;
        runs.push_back(r);
      }
    }
  }
  return runs;
}

std::vector<GrabCutRun> bench_grabcut(Device& dev, const std::string& data, uint32_t images, uint32_t iterations,
                                      MinCutSolver solver, Parallelism* parallelism) {
  ParallelismMeter meter(dev);
  std::vector<GrabCutRun> runs;
  const auto names = image_names(data);
  const size_t count = images == 0 ? names.size() : std::min<size_t>(images, names.size());
  for (size_t k = 0; k < count; ++k) {
    const RasterImage img = io::read_image((fs::path(data) / "images" / (names[k] + ".ppm")).string());
    const RasterImage truth = io::read_image((fs::path(data) / "masks" / (names[k] + ".pgm")).string());
    MaskStart start;
    start.box = mask::box_from_truth(truth.samples, img.width, img.height);
    MaskOptions o;
    o.iterations = iterations;
    o.post = false;
    o.min_cut_solver = solver;
    if (parallelism) meter.start();
    const auto t0 = Clock::now();
    const MaskResult r = mask_image(dev, img, start, o);
    const double seconds = since(t0);
    if (parallelism) accumulate(*parallelism, meter.stop());
    GrabCutRun run{names[k], img.width, img.height, r.iterations, seconds, mask::mask_error(r.mask, truth.samples), 0};
    run.post_error = mask::mask_error(postprocess_mask(dev, r.grabcut, img.width, img.height, MaskOptions{}.erode_radius),
                                      truth.samples);
    if (baseline::opencv().built_in && img.channels == 3 && img.max_value == 255) {
      const std::vector<uint8_t> rgb(img.samples.begin(), img.samples.end());
      const MaskBox& b = *start.box;
      const auto cv = baseline::opencv_grabcut(rgb, img.width, img.height, {b.x, b.y, b.w, b.h}, iterations);
      run.opencv = true;
      run.opencv_seconds = cv.seconds;
      run.opencv_error = mask::mask_error(cv.mask, truth.samples);
    }
    runs.push_back(run);
  }
  return runs;
}

}  // namespace mv::bench
