// `megavox bench cache`: a camera flight through the device page cache against the resident render.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

#include "flight_bench.h"
#include "cli_common.h"
#include "megavox/error.h"
#include "megavox/trace.h"

namespace mv::cli {

void add_bench_cache_command(CLI::App& bench, const GlobalOptions& g) {
  struct Args {
    std::string input, cache_memory = "16M", path, shading = "shaded";
    uint32_t frames = 8;
    double distance = 0.6, fov = 40;
    RenderOptions opt;
    std::string read_ahead = "auto";
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  a->opt.width = 640;
  a->opt.height = 480;
  auto* cmd = bench.add_subcommand(
      "cache",
      "Render a camera flight over a paged .mvx through the device page cache (--cache-memory) and, in the same\n"
      "run, the fully resident render of the same file with today's kernel. Reports frame times of both, the\n"
      "share of the paged frame spent in cache management (stamp, LRU, request and invalidation kernels and\n"
      "the host's waits), reading and uploading pages apart, bytes streamed per frame, the hit rate, frames\n"
      "byte-identical to the resident render, and the address layer's cost on the resident path: the paged\n"
      "kernel through a second cache holding every page of the view (as large as one allocation allows)\n"
      "against today's kernel, per view, best of 5 each in pairs of alternating order. Default flight:\n"
      "--frames cameras orbiting the model at --distance times the distance that frames it.");
  cmd->add_option("file", a->input, "A paged .mvx (built by this version; any encoding)")->required();
  cmd->add_option("--cache-memory", a->cache_memory, "Page cache size")->capture_default_str();
  cmd->add_option("--path", a->path, "A camera flight (JSON, see `megavox render --help`) instead of the orbit");
  cmd->add_option("--frames", a->frames, "Orbit frames")->capture_default_str();
  cmd->add_option("--distance", a->distance, "Orbit radius, as a multiple of the framing distance")
      ->capture_default_str();
  cmd->add_option("--fov", a->fov, "Vertical field of view of the orbit, degrees")->capture_default_str();
  cmd->add_option("--width", a->opt.width, "Image width")->capture_default_str();
  cmd->add_option("--height", a->opt.height, "Image height")->capture_default_str();
  cmd->add_option("--shading", a->shading, "shaded, normal, depth, level or heat")->capture_default_str();
  cmd->add_option("--ao-samples", a->opt.ao_samples, "Ambient-occlusion rays per hit")->capture_default_str();
  cmd->add_option("--lod-pixels", a->opt.lod_pixels, "Stop at cells smaller than this many pixels")
      ->capture_default_str();
  cmd->add_option("--read-ahead", a->read_ahead,
                  "Read the primary rays' missing pages while shadow and AO rays trace: on, off, or auto (on GPUs)")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  cmd->add_flag("--json", a->json, "Print one JSON object");
  cmd->callback([&g, a] {
    a->opt.shading = parse_shading(a->shading);
    if (a->read_ahead != "auto") a->opt.read_ahead = a->read_ahead == "on";
    if (a->frames == 0 && a->path.empty()) throw Error("--frames must be at least 1");
    auto dev = open_device(g);
    std::vector<Camera> flight = !a->path.empty()
                                     ? read_flight(a->path)
                                     : bench::orbit_flight(open_paged_mvx(a->input).bounds, a->frames, a->distance,
                                                           a->fov);
    const bench::FlightBenchResult r =
        bench::run_flight_bench(*dev, a->input, flight, a->opt, parse_size(a->cache_memory));
    if (g.profile) print_kernel_totals(*dev);
    const double n = double(r.frames.size());
    const double paged_bytes = double(r.pages) * r.page_words * 4, cache_bytes = double(r.slots) * r.page_words * 4;
    if (a->json) {
      nlohmann::json frames = nlohmann::json::array();
      for (const bench::FlightFrame& f : r.frames)
        frames.push_back({{"resident_seconds", f.resident_seconds}, {"paged_seconds", f.paged_seconds},
                          {"passes", f.passes}, {"converged", f.converged}, {"identical", f.identical},
                          {"cache_seconds", f.manage_seconds}, {"io_seconds", f.produce_seconds},
                          {"read_ahead_seconds", f.read_ahead_seconds}, {"pages_read_ahead", f.pages_read_ahead},
                          {"pages_loaded", f.pages_loaded}, {"pages_evicted", f.pages_evicted},
                          {"bytes_uploaded", f.bytes_uploaded}, {"hit_rate", f.hit_rate},
                          {"resident_trace_seconds", f.resident_trace_seconds},
                          {"warm_paged_trace_seconds", f.last_pass_trace_seconds},
                          {"warm_resident_trace_seconds", f.resident_best_trace_seconds}});
      nlohmann::json j = {{"benchmark", "cache"}, {"device", dev->info().name}, {"file", a->input},
                          {"pages", r.pages}, {"page_words", r.page_words}, {"slots", r.slots},
                          {"dag_over_cache", cache_bytes > 0 ? paged_bytes / cache_bytes : 0.0},
                          {"width", a->opt.width}, {"height", a->opt.height}, {"shading", a->shading},
                          {"resident_frame_seconds", r.resident_seconds / n}, {"paged_frame_seconds", r.paged_seconds / n},
                          {"cache_share", r.manage_share}, {"io_share", r.paged_seconds > 0 ? r.produce_seconds / r.paged_seconds : 0.0},
                          {"bytes_per_frame", double(r.bytes_uploaded) / n}, {"hit_rate", r.hit_rate},
                          {"pages_read_ahead", r.pages_read_ahead}, {"read_ahead_seconds", r.read_ahead_seconds},
                          {"read_ahead", a->read_ahead},
                          {"identical_frames", r.identical}, {"address_layer_cost", r.address_cost}, {"address_cache_slots", r.warm_slots},
                          {"frames", frames}};
      std::cout << j.dump(2) << "\n";
      return;
    }
    std::printf("page cache flight on %s: %s, %u pages of %u words (%.1f MiB), %u slots (%.1f MiB, DAG / cache %.1f)\n",
                dev->info().name.c_str(), a->input.c_str(), r.pages, r.page_words, paged_bytes / 1048576.0, r.slots,
                cache_bytes / 1048576.0, cache_bytes > 0 ? paged_bytes / cache_bytes : 0.0);
    std::printf("  %-5s %10s %10s %6s %9s %9s %8s %10s %8s %9s\n", "frame", "resident s", "paged s", "passes",
                "cache %", "io %", "loaded", "MiB", "hit rate", "identical");
    for (size_t i = 0; i < r.frames.size(); ++i) {
      const bench::FlightFrame& f = r.frames[i];
      std::printf("  %-5zu %10.3f %10.3f %6u %9.2f %9.2f %8llu %10.2f %8.3f %9s\n", i, f.resident_seconds,
                  f.paged_seconds, f.passes, 100 * f.manage_seconds / f.paged_seconds,
                  100 * f.produce_seconds / f.paged_seconds, (unsigned long long)f.pages_loaded,
                  f.bytes_uploaded / 1048576.0, f.hit_rate, f.identical ? "yes" : "NO");
    }
    std::printf("  mean frame: resident %.3f s, paged %.3f s (ratio %.2f); cache management %.2f %% of paged frame "
                "time, reading and uploading %.2f %%\n",
                r.resident_seconds / n, r.paged_seconds / n, r.resident_seconds > 0 ? r.paged_seconds / r.resident_seconds : 0,
                100 * r.manage_share, r.paged_seconds > 0 ? 100 * r.produce_seconds / r.paged_seconds : 0.0);
    std::printf("  %.2f MiB streamed per frame, hit rate %.3f, %u of %zu frames byte-identical to the resident render\n",
                r.bytes_uploaded / n / 1048576.0, r.hit_rate, r.identical, r.frames.size());
    std::printf("  %llu pages read ahead while shadow and AO rays traced (%.3f s on their own thread)\n",
                (unsigned long long)r.pages_read_ahead, r.read_ahead_seconds);
    if (r.warm_slots)
      std::printf("  address layer on the resident path: paged kernel, every page resident (%u slots) / today's "
                  "kernel = %.3f\n", r.warm_slots, r.address_cost);
    else
      std::printf("  address layer: not measured (no room for a cache of the whole view beside the resident DAG)\n");
  });
}

}  // namespace mv::cli
