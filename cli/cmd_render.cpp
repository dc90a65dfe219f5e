// `megavox render`: a picture of a .mvx file through the traversal kernel.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

#include "cli_common.h"
#include "megavox/error.h"
#include "megavox/render.h"
#include "megavox/trace.h"

namespace mv::cli {

void add_render_command(CLI::App& app, const GlobalOptions& g) {
  struct Args {
    std::string input, output, view = "iso", eye, target, up = "0,1,0", shading = "shaded";
    double fov = 40;
    RenderOptions opt;
    bool json = false, quiet = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = app.add_subcommand("render", "Render a .mvx file to a PNG picture through the ray traversal kernel");
  cmd->footer(
      "Camera: a preset view framing the model (--view), or --eye/--target/--up/--fov in the model's own\n"
      "units (the coordinates of the mesh the file was built from). Shading: shaded (light, hard shadows and\n"
      "ambient occlusion), normal, depth, level (false colour per level of detail) or heat (traversal steps).\n"
      "Rays stop at cells smaller than --lod-pixels pixels (0: always go down to voxels).\n\n"
      "Examples:\n"
      "  megavox render bunny.mvx -o bunny.png\n"
      "  megavox render bunny.mvx -o front.png --view front --width 1280 --height 720 --shading normal\n"
      "  megavox render bunny.mvx -o close.png --eye 0.1,0.2,0.3 --target 0,0.1,0 --fov 30 --lod-pixels 0\n");
  cmd->add_option("file", a->input, "The .mvx file")->required();
  cmd->add_option("-o,--output", a->output, "The PNG to write")->required();
  cmd->add_option("--width", a->opt.width, "Image width in pixels")->capture_default_str();
  cmd->add_option("--height", a->opt.height, "Image height in pixels")->capture_default_str();
  cmd->add_option("--view", a->view, "Preset camera: front, back, left, right, top or iso")->capture_default_str();
  cmd->add_option("--eye", a->eye, "Camera position X,Y,Z (replaces --view)");
  cmd->add_option("--target", a->target, "Point looked at X,Y,Z (default: the model's centre)");
  cmd->add_option("--up", a->up, "Up direction X,Y,Z")->capture_default_str();
  cmd->add_option("--fov", a->fov, "Vertical field of view in degrees")->capture_default_str();
  cmd->add_option("--shading", a->shading, "shaded, normal, depth, level or heat")->capture_default_str();
  cmd->add_option("--lod-pixels", a->opt.lod_pixels, "Stop at cells smaller than this many pixels; 0 = voxels")
      ->capture_default_str();
  cmd->add_option("--ao-samples", a->opt.ao_samples, "Ambient-occlusion rays per hit (shaded)")->capture_default_str();
  cmd->add_option("--ao-radius", a->opt.ao_radius, "Ambient-occlusion radius in model units (0: 1/20 of the grid)")
      ->capture_default_str();
  cmd->add_flag("--json", a->json, "Print one JSON object instead of the summary");
  cmd->add_flag("--quiet", a->quiet, "Print nothing but errors");
  cmd->callback([a, &g] {
    MvxFile file = read_mvx(a->input);
    a->opt.shading = parse_shading(a->shading);
    Camera cam = view_camera(file.bounds, a->view, a->fov);
    if (!a->eye.empty()) {
      parse_vec3(a->eye, "--eye", cam.eye);
      if (!a->target.empty()) parse_vec3(a->target, "--target", cam.target);
      parse_vec3(a->up, "--up", cam.up);
    } else if (!a->target.empty()) {
      throw Error("--target needs --eye (or use --view)");
    }
    auto dev = open_device(g);
    Tracer tracer(*dev, file);
    RenderResult r = render(tracer, cam, a->opt);
    write_png(a->output, r.image);
    if (g.profile) print_kernel_totals(*dev);
    if (a->quiet) return;
    if (a->json) {
      nlohmann::json passes = nlohmann::json::array();
      for (const RenderPass& p : r.passes)
        passes.push_back({{"name", p.name}, {"rays", p.rays}, {"seconds", p.seconds},
                          {"mrays_per_second", p.seconds > 0 ? p.rays / p.seconds / 1e6 : 0.0}});
      nlohmann::json j = {{"file", a->input}, {"output", a->output}, {"device", dev->info().name},
                          {"format", encoding_name(file.dag.encoding)}, {"width", a->opt.width},
                          {"height", a->opt.height}, {"shading", a->shading}, {"lod_pixels", a->opt.lod_pixels},
                          {"eye", {cam.eye[0], cam.eye[1], cam.eye[2]}},
                          {"target", {cam.target[0], cam.target[1], cam.target[2]}}, {"fov", cam.fov},
                          {"hits", r.hits}, {"passes", passes}};
      std::cout << j.dump(2) << "\n";
      return;
    }
    std::printf("%s (%s, %u^3) -> %s: %ux%u %s on %s, %llu of %llu pixels hit\n", a->input.c_str(),
                encoding_name(file.dag.encoding).c_str(), file.grid.resolution, a->output.c_str(), a->opt.width,
                a->opt.height, a->shading.c_str(), dev->info().name.c_str(), (unsigned long long)r.hits,
                (unsigned long long)a->opt.width * a->opt.height);
    for (const RenderPass& p : r.passes)
      std::printf("  %-8s %12llu rays %9.3f s %9.2f Mrays/s\n", p.name.c_str(), (unsigned long long)p.rays, p.seconds,
                  p.seconds > 0 ? p.rays / p.seconds / 1e6 : 0.0);
  });
}

}  // namespace mv::cli
