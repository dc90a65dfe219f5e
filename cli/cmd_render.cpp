// `megavox render`: a picture of a .mvx file through the traversal kernel.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>

#include "camera_options.h"
#include "cli_common.h"
#include "io/atomic_dir.h"
#include "io/output_path.h"
#include "trace/trace_engine.h"
#include "megavox/error.h"
#include "megavox/render.h"
#include "megavox/trace.h"

namespace mv::cli {

namespace {

// One frame's cache figures, summed over its passes (a paged render; empty otherwise).
nlohmann::json cache_json(const RenderResult& r, double frame_seconds) {
  const CacheTotals t = cache_totals(r.cache);
  nlohmann::json j = {{"passes", r.cache.size()}, {"converged", r.converged}, {"tiles", r.tiles}, {"pages_requested", t.requested},
                      {"pages_loaded", t.loaded}, {"pages_evicted", t.evicted}, {"pages_failed", t.failed},
                      {"hit_rate", t.hit_rate()}, {"bytes_uploaded", t.bytes_uploaded},
                      {"cache_seconds", t.manage_seconds}, {"io_seconds", t.produce_seconds},
                      {"pages_read_ahead", t.read_ahead}, {"read_ahead_seconds", t.read_ahead_seconds},
                      {"trace_seconds", r.trace_seconds}, {"frame_seconds", frame_seconds},
                      {"cache_share", frame_seconds > 0 ? t.manage_seconds / frame_seconds : 0.0},
                      {"coarse_pixels", r.coarse_pixels}};
  for (const CacheUpdateStats& st : r.cache)
    if (!st.first_error.empty()) {
      j["first_error"] = st.first_error;
      break;
    }
  return j;
}

// A frame's passes summed by kind (primary, shadow, ao), in order: a banded frame has a set per band.
std::vector<RenderPass> passes_by_name(const std::vector<RenderPass>& passes) {
  std::vector<RenderPass> sums;
  for (const RenderPass& p : passes) {
    auto it = std::find_if(sums.begin(), sums.end(), [&](const RenderPass& s) { return s.name == p.name; });
    if (it == sums.end()) it = sums.insert(sums.end(), {p.name, 0, 0});
    it->rays += p.rays;
    it->seconds += p.seconds;
  }
  return sums;
}

// The frames of a paged render that show a coarser level somewhere, and why: warned about once, at the end.
struct CoarseFrames {
  size_t frames = 0;
  uint64_t pixels = 0;
  std::string first;        // the first such frame's file
  std::string read_error;   // the first page that could not be read
  bool over_capacity = false;

  void add(const RenderResult& r, const std::string& file) {
    if (r.converged) return;
    if (frames++ == 0) first = file;
    pixels += r.coarse_pixels;
    for (const CacheUpdateStats& st : r.cache) {
      over_capacity = over_capacity || st.over_capacity;
      if (read_error.empty()) read_error = st.first_error;
    }
  }

  // One line on stderr; --cache-passes is named only when the user gave it, for nothing else can end a frame early.
  void warn(size_t total, bool passes_given) const {
    if (frames == 0) return;
    const std::string why =
        !read_error.empty() ? "pages could not be read (" + read_error + ")"
        : over_capacity     ? "the view needs more pages than --cache-memory holds (raise it, or --lod-pixels)"
        : passes_given      ? "--cache-passes ended the frame first"
                            : "the page cache could not load every page the view needs";
    if (total == 1)
      std::fprintf(stderr, "megavox: warning: %s: %llu pixels show a coarser level: %s\n", first.c_str(),
                   (unsigned long long)pixels, why.c_str());
    else
      std::fprintf(stderr,
                   "megavox: warning: %zu of %zu frames (the first %s) show a coarser level in %llu pixels: %s\n",
                   frames, total, first.c_str(), (unsigned long long)pixels, why.c_str());
  }
};

}  // namespace

std::string image_format(const std::string& path) {
  return io::format_of_extension(path) == "jpeg" ? "jpeg" : "png";
}

void add_render_command(CLI::App& app, const GlobalOptions& g) {
  struct Args {
    std::string input, output, shading = "shaded", cache_memory, path;
    CameraArgs camera;
    RenderOptions opt;
    bool no_clobber = false, no_colour = false, no_beam = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("render", "Render a .mvx file to a PNG picture through the ray traversal kernel");
  cmd->footer(
      "Camera: a preset view framing the model (--view), or --eye/--target/--up/--fov in the model's own\n"
      "units (the coordinates of the mesh the file was built from). Shading: shaded (light, hard shadows and\n"
      "ambient occlusion), normal, depth, level (false colour per level of detail), heat (traversal steps) or\n"
      "colour (the voxel colours unlit). A file with voxel colours (built from a coloured cloud) is shaded with\n"
      "them: a voxel's own colour, or where a ray stops at a coarser cell the mean of the voxels below it;\n"
      "--no-colour renders it grey. Rays stop at cells smaller than --lod-pixels pixels (0: always go down to\n"
      "voxels).\n\n"
      "Streaming: --cache-memory SIZE renders a paged file (built by this version: svo, svdag, ussvdag)\n"
      "through a device page cache of SIZE, which counts toward --device-memory: only the pages rays touch\n"
      "are read from the memory-mapped file. Each frame takes passes until no ray meets a missing page (the\n"
      "picture then equals the resident render, byte for byte) or --cache-passes. A view whose pages exceed\n"
      "the cache is rendered in bands of rows, halved until each band's pages fit (down to 1/256 of the\n"
      "frame); a cache too small even for those gives the finest level that fits, with a warning. A cache\n"
      "that holds every page is filled whole before the first frame, in page order: it renders at the\n"
      "resident speed from its first pass.\n"
      "Flights: --path FLIGHT.json renders every camera of {\"fov\": F, \"frames\": [{\"eye\": [x,y,z],\n"
      "\"target\": [x,y,z], \"up\": [x,y,z]}, ...]} (model units) into the folder -o DIR as frame_0000.png, ...;\n"
      "--json prints one JSON line per frame (pages requested, loaded and evicted, hit rate, bytes uploaded,\n"
      "time in cache management and in reading and uploading pages).\n\n"
      "Examples:\n"
      "  megavox render bunny.mvx -o bunny.png\n"
      "  megavox render bunny.mvx -o front.png --view front --width 1280 --height 720 --shading normal\n"
      "  megavox render bunny.mvx -o close.png --eye 0.1,0.2,0.3 --target 0,0.1,0 --fov 30 --lod-pixels 0\n"
      "  megavox render koala16k.mvx -o koala.png --cache-memory 16M\n"
      "  megavox render koala16k.mvx --path flight.json -o frames --cache-memory 16M --json\n");
  cmd->add_option("file", a->input, "The .mvx file")->required();
  cmd->add_option("-o,--output", a->output,
                  "The picture to write: PNG, or JPEG for a .jpg/.jpeg name (with --path: the folder of frames)")
      ->required();
  add_no_clobber_flag(*cmd, a->no_clobber);
  add_camera_options(*cmd, a->camera, "0,1,0", "Print JSON (one line per frame of a flight) instead of the summary");
  cmd->add_option("--path", a->path, "A camera flight (JSON): render its frames into the folder -o");
  cmd->add_option("--shading", a->shading, "shaded, normal, depth, level, heat or colour")->capture_default_str();
  cmd->add_flag("--no-colour", a->no_colour, "Shade grey even where the file has voxel colours");
  cmd->add_flag("--no-beam", a->no_beam,
                "Start every camera ray at the model's cube instead of where the beam pre-pass proves it may (the "
                "same picture, slower)");
  cmd->add_option("--lod-pixels", a->opt.lod_pixels, "Stop at cells smaller than this many pixels; 0 = voxels")
      ->capture_default_str();
  cmd->add_option("--ao-samples", a->opt.ao_samples, "Ambient-occlusion rays per hit (shaded)")->capture_default_str();
  cmd->add_option("--ao-radius", a->opt.ao_radius, "Ambient-occlusion radius in model units (0: 1/20 of the grid)")
      ->capture_default_str();
  cmd->add_option("--cache-memory", a->cache_memory, "Stream a paged file through a device page cache of SIZE (16M)");
  cmd->add_option("--cache-passes", a->opt.cache_passes, "Passes per frame (per band, when banded) at most when streaming; 0 = until complete")
      ->capture_default_str();
  cmd->callback([a, &g, cmd] {
    const CameraVectors v = camera_vectors(a->camera);
    a->opt.shading = with_code(ErrorCode::invalid_argument, [&] { return parse_shading(a->shading); });
    a->opt.colours = !a->no_colour;
    a->opt.beam = !a->no_beam;
    a->opt.width = a->camera.width;
    a->opt.height = a->camera.height;
    // Before the device opens or the file is read: a PNG or JPEG takes about a byte a pixel.
    const bool flight = !a->path.empty();
    const std::string output = io::resolve_output(
        {a->output, flight ? io::OutputKind::kFolder : io::OutputKind::kFile,
         flight ? "" : image_format(a->output), {a->input, a->path}, uint64_t{a->opt.width} * a->opt.height,
         a->no_clobber});
    auto dev = open_device(g);
    std::unique_ptr<Tracer> tracer;
    Bounds bounds;
    std::string format;
    uint32_t resolution = 0;
    if (!a->cache_memory.empty()) {
      PagedDag dag = open_paged_mvx(a->input);
      bounds = dag.bounds;
      format = encoding_name(dag.encoding);
      resolution = dag.grid.resolution;
      if (dag.has_colours && dag.plane_words == 0 && frame_uses_colours(a->opt) && !a->camera.quiet)
        std::fprintf(stderr, "megavox: %s has voxel colours, but no size plane to find them through the cache (it "
                             "was written before .mvx version 5): streaming shows geometry only; rebuild it, or "
                             "render without --cache-memory\n", a->input.c_str());
      if (!frame_uses_colours(a->opt)) dag.plane_words = 0;  // grey: the cache need not carry the plane
      tracer = std::make_unique<Tracer>(*dev, std::move(dag), parse_size(a->cache_memory));
    } else {
      MvxFile file = read_mvx(a->input);
      bounds = file.bounds;
      format = encoding_name(file.dag.encoding);
      resolution = file.grid.resolution;
      tracer = std::make_unique<Tracer>(*dev, file, frame_uses_colours(a->opt));
    }
    std::vector<Camera> cams;
    if (!a->path.empty()) {
      if (v.eye) throw CodedError(ErrorCode::invalid_argument, "--path gives the cameras: drop --eye and --target");
      cams = read_flight(a->path);
    } else {
      Camera cam = view_camera(bounds, a->camera.view, a->camera.fov);
      if (v.eye) {
        std::copy(v.eye->begin(), v.eye->end(), cam.eye);
        if (v.target) std::copy(v.target->begin(), v.target->end(), cam.target);
        const std::array<double, 3> up = v.up.value_or(std::array<double, 3>{0, 1, 0});
        std::copy(up.begin(), up.end(), cam.up);
      }
      cams.push_back(cam);
    }
    CoarseFrames coarse;
    auto render_frame = [&](size_t i, const std::string& png) {
      const auto t0 = std::chrono::steady_clock::now();
      RenderResult r = render(*tracer, cams[i], a->opt);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      write_image(png, r.image);
      coarse.add(r, flight ? output + png.substr(png.rfind('/')) : output);
      if (a->camera.quiet) return;
      if (a->camera.json) {
        nlohmann::json passes = nlohmann::json::array();
        for (const RenderPass& p : r.passes)
          passes.push_back({{"name", p.name}, {"rays", p.rays}, {"seconds", p.seconds},
                            {"mrays_per_second", p.seconds > 0 ? p.rays / p.seconds / 1e6 : 0.0}});
        const Camera& cam = cams[i];
        nlohmann::json j = {{"file", a->input}, {"output", png}, {"device", dev->info().name},
                            {"format", format}, {"width", a->opt.width},
                            {"height", a->opt.height}, {"shading", a->shading}, {"lod_pixels", a->opt.lod_pixels},
                            {"eye", {cam.eye[0], cam.eye[1], cam.eye[2]}},
                            {"target", {cam.target[0], cam.target[1], cam.target[2]}}, {"fov", cam.fov},
                            {"hits", r.hits}, {"seconds", seconds}, {"passes", passes},
                            {"colours", tracer->has_colours()},
                            {"colour_device_bytes", tracer->engine().colour_bytes()}};
        if (!a->path.empty()) j["frame"] = i;
        if (tracer->paged()) {
          j["cache"] = cache_json(r, seconds);
          j["cache"]["preloaded_pages"] = tracer->preloaded().loaded;  // the whole DAG fit: loaded before frame 0
        }
        std::cout << (a->path.empty() ? j.dump(2) : j.dump()) << "\n";
        return;
      }
      if (a->path.empty()) {
        std::printf("%s (%s, %u^3%s) -> %s: %ux%u %s on %s, %llu of %llu pixels hit\n", a->input.c_str(),
                    format.c_str(), resolution, tracer->has_colours() ? ", coloured" : "", png.c_str(), a->opt.width,
                    a->opt.height, a->shading.c_str(),
                    dev->info().name.c_str(), (unsigned long long)r.hits,
                    (unsigned long long)a->opt.width * a->opt.height);
        for (const RenderPass& p : passes_by_name(r.passes))
          std::printf("  %-8s %12llu rays %9.3f s %9.2f Mrays/s\n", p.name.c_str(), (unsigned long long)p.rays,
                      p.seconds, p.seconds > 0 ? p.rays / p.seconds / 1e6 : 0.0);
        if (r.tiles > 1) std::printf("  rendered in %u bands of rows\n", r.tiles);
      } else {
        std::printf("frame %zu: %llu pixels hit, %.3f s\n", i, (unsigned long long)r.hits, seconds);
      }
      if (tracer->paged() && i == 0 && tracer->preloaded().loaded > 0) {
        const CacheUpdateStats& pre = tracer->preloaded();
        std::printf("  cache: holds the whole DAG, preloaded before the frame: %u pages, %.1f MiB, %.3f s\n", pre.loaded,
                    pre.bytes_uploaded / 1048576.0, pre.manage_seconds + pre.produce_seconds);
      }
      if (tracer->paged()) {
        const nlohmann::json c = cache_json(r, seconds);
        std::printf("  cache: %zu passes%s, %llu pages loaded, %llu evicted, hit rate %.3f, %.1f MiB uploaded, "
                    "management %.1f %% of the frame, reading and uploading %.3f s\n",
                    r.cache.size(), r.converged ? "" : " (incomplete)",
                    (unsigned long long)c["pages_loaded"].get<uint64_t>(),
                    (unsigned long long)c["pages_evicted"].get<uint64_t>(), c["hit_rate"].get<double>(),
                    c["bytes_uploaded"].get<uint64_t>() / 1048576.0, 100 * c["cache_share"].get<double>(),
                    c["io_seconds"].get<double>());
      }
    };
    if (!flight) {
      render_frame(0, output);
    } else {
      io::write_dir_atomically(output, "frame_0000.png", [&](const std::string& dir) {
        for (size_t i = 0; i < cams.size(); ++i) {
          char name[32];
          std::snprintf(name, sizeof name, "/frame_%04zu.png", i);
          render_frame(i, dir + name);
        }
      });
    }
    if (!a->camera.quiet) coarse.warn(cams.size(), cmd->count("--cache-passes") > 0);
    if (g.profile) print_kernel_totals(*dev);
  });
}

}  // namespace mv::cli
