#include "build_plan_text.h"

#include <cstdio>
#include <string>

namespace mv::cli {

namespace {
std::string count_text(uint64_t n) {
  if (n >= 10'000'000'000ull) return std::to_string(n / 1'000'000'000) + "G";
  if (n >= 10'000'000) return std::to_string(n / 1'000'000) + "M";
  if (n >= 10'000) return std::to_string(n / 1'000) + "K";
  return std::to_string(n);
}
}  // namespace

void print_plan(const BuildPlan& p) {
  std::fprintf(stderr, "megavox: plan: %u^3 grid, voxel %.6g, origin %.6g,%.6g,%.6g; ", p.resolution, p.voxel_size,
               p.origin[0], p.origin[1], p.origin[2]);
  if (p.out_of_core)
    std::fprintf(stderr, "out of core in cubes of %u^3 (%s cubes, about %s meeting the surface)\n", p.cube,
                 count_text(p.cubes).c_str(), count_text(p.cubes_with_surface).c_str());
  else
    std::fprintf(stderr, "in core\n");
  std::fprintf(stderr, "megavox: estimated %s voxels, output %s; host memory %s, device memory %s%s\n",
               count_text(p.voxels).c_str(), format_bytes(p.output_bytes).c_str(), format_bytes(p.host_bytes).c_str(),
               format_bytes(p.device_bytes).c_str(), p.out_of_core ? " per cube" : "");
  for (const std::string& w : p.warnings) std::fprintf(stderr, "megavox: warning: %s\n", w.c_str());
}

nlohmann::json plan_json(const BuildPlan& p) {
  return {{"resolution", p.resolution},
          {"voxel_size", p.voxel_size},
          {"origin", p.origin},
          {"triangles", p.triangles},
          {"surface_area", p.surface_area},
          {"out_of_core", p.out_of_core},
          {"cube", p.cube},
          {"cubes", p.cubes},
          {"cubes_with_surface", p.cubes_with_surface},
          {"estimated_voxels", p.voxels},
          {"estimated_output_bytes", p.output_bytes},
          {"estimated_host_bytes", p.host_bytes},
          {"estimated_device_bytes", p.device_bytes},
          {"warnings", p.warnings}};
}

}  // namespace mv::cli
