// `megavox bench attributes`: voxel colours on coloured clouds: bits per voxel against raw storage, the thesis's
// compression rate and ΔE94 per quantization, and their time and memory against the colourless build and render.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "attributes_bench.h"
#include "cli_common.h"
#include "megavox/error.h"

namespace mv::cli {

namespace {

// The coloured clouds of the shared test data that the benchmark uses when given none.
std::vector<std::string> attribute_clouds(const std::string& data) {
  std::vector<std::string> out;
  for (const char* f : {"pointcloud_autzen/autzen_trim.las", "pointcloud_lion_takanawa/lion_takanawa.ply",
                        "rgbd_kinect/milk_cartoon_clorox.ply", "rgbd_kinect/region_growing_rgb.ply"})
    if (std::filesystem::exists(data + "/" + f)) out.push_back(data + "/" + f);
  return out;
}

nlohmann::json attribute_build_json(const bench::AttributeBuild& b, const bench::AttributeBuild& grey) {
  nlohmann::json j = {{"colour_bits", b.bits},
                      {"stage_seconds", b.stage_seconds},
                      {"stage_ratio", grey.stage_seconds > 0 ? b.stage_seconds / grey.stage_seconds : 0.0},
                      {"peak_rss_bytes", b.peak_rss_bytes},
                      {"peak_rss_ratio", grey.peak_rss_bytes ? double(b.peak_rss_bytes) / double(grey.peak_rss_bytes) : 0.0},
                      {"colour_format", b.report.colour_format},
                      {"colour_bytes", b.colour_bytes},
                      {"colour_bits_per_voxel", b.colour_bits_per_voxel},
                      {"raw_bits_per_voxel", b.raw_bits_per_voxel},
                      {"compression_rate", b.compression_rate},
                      {"palette_seconds", b.report.colour_palette_seconds}};
  const ColourQuantizeReport& q = b.report.colour_quantize;
  if (b.bits < 24)
    j["quantize"] = {{"colours_in", q.colours_in}, {"colours_out", q.colours_out}, {"delta_e94_mean", q.mean_delta_e},
                     {"delta_e94_max", q.max_delta_e}, {"seconds", q.seconds}};
  return j;
}

}  // namespace

void add_bench_attributes_command(CLI::App& bench, const GlobalOptions& g) {
  struct Args {
    std::vector<std::string> clouds;
    std::string data = "../shared/data", resolution = "1K";
    bench::AttributesBenchOptions opt;
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  a->opt.render.width = 640;
  a->opt.render.height = 480;
  auto* cmd = bench.add_subcommand(
      "attributes",
      "Voxel colours on coloured point clouds (docs/colour.md). Each cloud is built at --resolution with\n"
      "--grid-origin min: once without colour, then with colour at each --bits (24 = lossless), each the fastest\n"
      "of --repeats runs with kernels compiled. Reports the colour section's bits per voxel against raw storage\n"
      "(24 bits an entry), the compression rate as Kol's thesis defines it (the section / the raw attribute\n"
      "array), ΔE94 of the quantized colours, the build's stages (read and write excluded) and host peak memory\n"
      "against the colourless build, and the shaded render of the lossless file with its colours against grey.\n\n"
      "Example: megavox bench attributes --data ../shared/data --json");
  cmd->add_option("clouds", a->clouds,
                  "Coloured clouds (LAS, PLY) or meshes (vertex colours, textures); default: the coloured clouds under "
                  "--data");
  cmd->add_option("--data", a->data, "The shared test data folder")->capture_default_str();
  cmd->add_option("--resolution", a->resolution, "Voxels per axis (a power of two: 512, 1K, 2K, ...)")
      ->capture_default_str();
  cmd->add_option("--bits", a->opt.bits, "Colour bits to build with (24, 16, 14, 12)")->delimiter(',');
  cmd->add_option("--repeats", a->opt.repeats, "Runs per build and render (the fastest counts)")->capture_default_str();
  cmd->add_option("--width", a->opt.render.width, "Render width")->capture_default_str();
  cmd->add_option("--height", a->opt.render.height, "Render height")->capture_default_str();
  cmd->add_flag("--json", a->json, "Print one JSON object");
  cmd->callback([&g, a] {
    if (a->clouds.empty()) a->clouds = attribute_clouds(a->data);
    if (a->clouds.empty()) throw Error("no clouds given, and none of the coloured clouds is under " + a->data);
    if (a->opt.repeats == 0) throw Error("--repeats must be at least 1");
    a->opt.resolution = parse_resolution(a->resolution);
    auto dev = open_device(g);
    nlohmann::json all = nlohmann::json::array();
    for (const std::string& cloud : a->clouds) {
      if (!a->json) std::fprintf(stderr, "attributes: %s\n", cloud.c_str());
      const bench::AttributesBenchResult r = bench::bench_attributes(*dev, cloud, a->opt);
      nlohmann::json j = {{"input", r.input}, {"points", r.points}, {"triangles", r.triangles}, {"voxels", r.voxels},
                          {"entries", r.entries},
                          {"colourless", attribute_build_json(r.colourless, r.colourless)},
                          {"render_seconds", r.render_seconds}, {"grey_render_seconds", r.grey_render_seconds},
                          {"render_ratio", r.grey_render_seconds > 0 ? r.render_seconds / r.grey_render_seconds : 0.0},
                          {"colour_pass_seconds", r.colour_pass_seconds}, {"hits", r.hits},
                          {"pixels_changed", r.pixels_changed}, {"peak_rss_reset", r.peak_rss_reset}};
      j["coloured"] = nlohmann::json::array();
      for (const auto& b : r.coloured) j["coloured"].push_back(attribute_build_json(b, r.colourless));
      all.push_back(j);
      if (g.profile) print_kernel_totals(*dev);
      if (a->json) continue;
      std::printf("%s: %llu %s, %llu voxels, %llu colour entries\n", cloud.c_str(),
                  (unsigned long long)(r.points ? r.points : r.triangles), r.points ? "points" : "triangles",
                  (unsigned long long)r.voxels, (unsigned long long)r.entries);
      std::printf("  colourless: stages %.3f s, peak RSS %.0f MiB\n", r.colourless.stage_seconds,
                  r.colourless.peak_rss_bytes / 1048576.0);
      for (const auto& b : r.coloured) {
        std::printf("  %2u bits: %-7s %6.1f bits/voxel (raw %.1f), rate %5.1f %%", b.bits, b.report.colour_format.c_str(),
                    b.colour_bits_per_voxel, b.raw_bits_per_voxel, 100 * b.compression_rate);
        if (b.bits < 24)
          std::printf(", ΔE94 %.2f mean, %.2f max", b.report.colour_quantize.mean_delta_e, b.report.colour_quantize.max_delta_e);
        std::printf("; stages %.3f s = %.2fx, peak RSS %.2fx\n", b.stage_seconds,
                    r.colourless.stage_seconds > 0 ? b.stage_seconds / r.colourless.stage_seconds : 0.0,
                    r.colourless.peak_rss_bytes ? double(b.peak_rss_bytes) / double(r.colourless.peak_rss_bytes) : 0.0);
      }
      std::printf("  render %ux%u shaded: %.3f s coloured (colour pass %.3f s), %.3f s grey = %.2fx; %llu of %llu hit "
                  "pixels differ from grey\n",
                  a->opt.render.width, a->opt.render.height, r.render_seconds, r.colour_pass_seconds,
                  r.grey_render_seconds, r.grey_render_seconds > 0 ? r.render_seconds / r.grey_render_seconds : 0.0,
                  (unsigned long long)r.pixels_changed, (unsigned long long)r.hits);
    }
    if (a->json) std::cout << nlohmann::json({{"device", dev->info().name}, {"clouds", all}}).dump(2) << "\n";
  });
}

}  // namespace mv::cli
