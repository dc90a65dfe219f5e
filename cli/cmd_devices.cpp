// `megavox devices`: every OpenCL and Vulkan device, with the limits that matter to megavox.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

#include "cli_common.h"

namespace mv::cli {

namespace {

nlohmann::json to_json(const DeviceInfo& d, bool selected) {
  return {{"selector", d.selector()},
          {"backend", d.backend},
          {"name", d.name},
          {"platform", d.platform},
          {"driver", d.driver},
          {"api_version", d.api_version},
          {"type", d.type},
          {"compute_units", d.compute_units},
          {"global_memory_bytes", d.global_memory_bytes},
          {"max_allocation_bytes", d.max_allocation_bytes},
          {"max_binding_bytes", d.max_binding_bytes},
          {"local_memory_bytes", d.local_memory_bytes},
          {"max_work_group_size", d.max_work_group_size},
          {"subgroup_size", d.subgroup_size},
          {"fp64", d.fp64},
          {"int64", d.int64},
          {"max_loop_iterations", d.max_loop_iterations},
          {"atomics64", d.atomics64},
          {"shared_atomics64", d.shared_atomics64},
          {"kernel_shape", d.massively_parallel ? "gpu" : "cpu"},  // in effect: by type, or --kernel-shape
          {"massively_parallel", d.massively_parallel},
          {"simd_width", d.simd_width},
          {"preferred_work_group_size", d.preferred_work_group_size},
          {"cheap_parameter_loads", d.cheap_parameter_loads},
          {"selected", selected}};
}

}  // namespace

void add_devices_command(CLI::App& app, const GlobalOptions& g) {
  auto* cmd = app.add_subcommand("devices", "List the OpenCL and Vulkan compute devices; * marks the one "
                                            "megavox would use (--device / MEGAVOX_DEVICE or the default); "
                                            "--json shows each one's launch shape under --kernel-shape");
  auto json = std::make_shared<bool>(false);
  cmd->add_flag("--json", *json, "Print one JSON array instead of the table");
  cmd->callback([&g, json] {
    auto all = list_devices();
    const KernelShape shape = with_code(ErrorCode::invalid_argument, [&] { return kernel_shape(g); });
    for (DeviceInfo& d : all) apply_kernel_shape(d, shape);
    // throws, listing the devices, when nothing matches
    DeviceInfo chosen = with_code(ErrorCode::unsupported_device, [&] { return select_device(g.device); });
    auto is_chosen = [&](const DeviceInfo& d) { return d.backend == chosen.backend && d.index == chosen.index; };
    if (*json) {
      nlohmann::json arr = nlohmann::json::array();
      for (const auto& d : all) arr.push_back(to_json(d, is_chosen(d)));
      std::cout << arr.dump(2) << "\n";
      return;
    }
    std::printf("  %-7s %-6s %-4s %-34s %-28s %4s %10s %10s %10s %6s %4s %4s\n", "device", "api", "type", "name",
                "platform", "CUs", "memory", "max alloc", "binding", "wg", "sg", "fp64");
    for (const auto& d : all) {
      std::string cu = d.compute_units ? std::to_string(d.compute_units) : "-";
      std::string sg = d.subgroup_size ? std::to_string(d.subgroup_size) : "-";
      std::printf("%s %-7s %-6s %-4s %-34.34s %-28.28s %4s %10s %10s %10s %6u %4s %4s\n", is_chosen(d) ? "*" : " ",
                  d.selector().c_str(), d.backend.c_str(), d.type.c_str(), d.name.c_str(), d.platform.c_str(),
                  cu.c_str(), format_bytes(d.global_memory_bytes).c_str(),
                  format_bytes(d.max_allocation_bytes).c_str(), format_bytes(d.max_binding_bytes).c_str(),
                  d.max_work_group_size, sg.c_str(), d.fp64 ? "yes" : "no");
    }
  });
}

}  // namespace mv::cli
