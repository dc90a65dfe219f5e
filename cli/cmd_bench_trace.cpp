// `megavox bench trace`: rays per second of the traversal kernel against Embree on the source triangles.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

#include "baselines.h"
#include "trace_bench.h"
#include "cli_common.h"
#include "megavox/error.h"

namespace mv::cli {

void add_bench_trace_command(CLI::App& bench, const GlobalOptions& g) {
  struct Args {
    std::vector<std::string> files;
    std::string mesh, eye, target, up = "0,1,0", cache_memory;
    bench::TraceBenchOptions o;
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = bench.add_subcommand(
      "trace",
      "Trace the renderer's rays through one or more .mvx files (e.g. the svdag and ssvdag builds of one mesh):\n"
      "Mrays/s of primary, shadow and ambient-occlusion rays on the device (best of --repeats), the same primary\n"
      "rays through the kernel's code built for the host and through the flat reference DDA, and Embree 3\n"
      "(rtcIntersect1 on all threads) on the source triangles with the same camera rays: the rate ratio and the\n"
      "share of pixels where voxels and triangles agree on hit or miss. With svdag and ssvdag files: the\n"
      "SSVDAG/SVDAG primary time ratio. Steps per ray: the cells each kind of ray visits (descents and moves),\n"
      "from the kernel's host build. Embree also runs rtcIntersect16 on 4 x 4 pixel packets. --cache-memory\n"
      "streams paged files through a device page cache of that size (the repeats after the first find their\n"
      "pages resident where the cache holds the view).\n"
      "Example:\n"
      "  megavox bench trace m_sv.mvx m_ss.mvx --mesh m.ply --repeats 5 --json\n"
      "  megavox bench trace koala16k.mvx --mesh koala.ply --cache-memory 64M");
  cmd->add_option("files", a->files, "The .mvx files (the first one's bounds frame the camera)")->required();
  cmd->add_option("--mesh", a->mesh, "The source mesh, traced by Embree (needs scripts/setup.sh --bench)");
  cmd->add_option("--width", a->o.width, "Image width")->capture_default_str();
  cmd->add_option("--height", a->o.height, "Image height")->capture_default_str();
  cmd->add_option("--view", a->o.view, "Preset camera (see render --help)")->capture_default_str();
  cmd->add_option("--eye", a->eye, "Camera position X,Y,Z in model units (with --target; replaces --view)");
  cmd->add_option("--target", a->target, "Point looked at X,Y,Z");
  cmd->add_option("--up", a->up, "Up direction X,Y,Z")->capture_default_str();
  cmd->add_option("--fov", a->o.camera.fov, "Vertical field of view in degrees (with --eye)")->capture_default_str();
  cmd->add_option("--lod-pixels", a->o.lod_pixels, "Level-of-detail threshold in pixels; 0 = voxels")
      ->capture_default_str();
  cmd->add_option("--ao-samples", a->o.ao_samples, "Ambient-occlusion rays per hit")->capture_default_str();
  cmd->add_option("--repeats", a->o.repeats, "Runs per figure (the best is kept)")->capture_default_str();
  cmd->add_option("--cache-memory", a->cache_memory, "Trace paged files through a device page cache of SIZE (64M)");
  cmd->add_flag("--json", a->json, "Print one JSON object");
  cmd->callback([&g, a] {
    if (!a->eye.empty() || !a->target.empty()) {
      if (a->eye.empty() || a->target.empty()) throw Error("--eye and --target go together");
      parse_vec3(a->eye, "--eye", a->o.camera.eye);
      parse_vec3(a->target, "--target", a->o.camera.target);
      parse_vec3(a->up, "--up", a->o.camera.up);
      a->o.use_camera = true;
    }
    if (!a->cache_memory.empty()) a->o.cache_bytes = parse_size(a->cache_memory);
    auto dev = open_device(g);
    bench::TraceBenchResult r = bench::run_trace_bench(*dev, a->files, a->mesh, a->o);
    if (g.profile) print_kernel_totals(*dev);
    if (a->json) {
      nlohmann::json encs = nlohmann::json::array();
      for (const auto& e : r.encodings)
        encs.push_back({{"file", e.file}, {"format", e.format}, {"resolution", e.resolution}, {"hits", e.hits},
                        {"primary_mrays", e.primary_mrays}, {"primary_mrays_no_beam", e.primary_mrays_no_beam},
                        {"shadow_mrays", e.shadow_mrays},
                        {"ao_mrays", e.ao_mrays}, {"primary_seconds", e.primary_seconds},
                        {"host_core_mrays", e.host_core_mrays}, {"reference_mrays", e.reference_mrays},
                        {"over_embree", e.over_embree}, {"silhouette_agreement", e.silhouette_agreement},
                        {"paged", e.paged}, {"converged", e.converged},
                        {"steps_per_ray", {{"primary", e.steps.primary}, {"primary_hit", e.steps.primary_hit},
                                           {"shadow", e.steps.shadow}, {"ao", e.steps.ao},
                                           {"primary_rendered", e.beam_steps},
                                           {"primary_hit_rendered", e.beam_hit_steps}}}});
      nlohmann::json j = {{"benchmark", "trace"}, {"device", r.device}, {"mesh", r.mesh}, {"width", r.width},
                          {"height", r.height}, {"lod_pixels", r.lod_pixels}, {"encodings", encs},
                          {"cache_memory", a->o.cache_bytes},
                          {"embree", r.have_embree}, {"triangles", r.triangles},
                          {"embree_mrays", r.embree_mrays}, {"embree16_mrays", r.embree16_mrays},
                          {"embree16_mismatches", r.embree16_mismatches},
                          {"embree_build_seconds", r.embree_build_seconds},
                          {"embree_hits", r.embree_hits}, {"ssvdag_over_svdag", r.ssvdag_over_svdag},
                          {"ssvdag_over_svdag_primary", r.ssvdag_over_svdag_primary}};
      std::cout << j.dump(2) << "\n";
      return;
    }
    std::printf("%ux%u rays on %s, LOD %.3g px\n", r.width, r.height, r.device.c_str(), r.lod_pixels);
    std::printf("  %-8s %6s %10s %10s %10s %12s %12s %9s %10s\n", "format", "res", "primary", "shadow", "ao",
                "host core", "flat ref", "/embree", "silhouette");
    for (const auto& e : r.encodings)
      std::printf("  %-8s %6u %10.2f %10.2f %10.2f %12.2f %12.3f %9.2f %9.2f%%\n", e.format.c_str(), e.resolution,
                  e.primary_mrays, e.shadow_mrays, e.ao_mrays, e.host_core_mrays, e.reference_mrays, e.over_embree,
                  100 * e.silhouette_agreement);
    std::printf("  (Mrays/s)\n");
    for (const auto& e : r.encodings)
      if (e.primary_mrays_no_beam > 0)
        std::printf("  %-8s %6u primary without the beam pre-pass %.2f (the beam: %.2fx; steps with it %.1f, hits %.1f)\n",
                    e.format.c_str(), e.resolution, e.primary_mrays_no_beam, e.primary_mrays / e.primary_mrays_no_beam,
                    e.beam_steps, e.beam_hit_steps);
    std::printf("  steps per ray (cells visited):\n");
    for (const auto& e : r.encodings)
      std::printf("  %-8s %6u primary %.1f (hits %.1f), shadow %.1f, ao %.1f\n", e.format.c_str(), e.resolution,
                  e.steps.primary, e.steps.primary_hit, e.steps.shadow, e.steps.ao);
    if (r.have_embree)
      std::printf("  Embree 3: %llu triangles, scene %.3f s, %.2f Mrays/s primary (rtcIntersect1), %.2f (rtcIntersect16, "
                  "4 x 4 packets), %llu hits\n",
                  (unsigned long long)r.triangles, r.embree_build_seconds, r.embree_mrays, r.embree16_mrays,
                  (unsigned long long)r.embree_hits);
    else if (!a->mesh.empty())
      std::printf("  %s\n", mv::baseline::missing_note(mv::baseline::embree()).c_str());
    if (r.ssvdag_over_svdag > 0)
      std::printf("  SSVDAG/SVDAG trace time: %.3f (median of back-to-back renders); primary pass, best times: %.3f\n",
                  r.ssvdag_over_svdag, r.ssvdag_over_svdag_primary);
  });
}

}  // namespace mv::cli
