// What every megavox subcommand shares: the global options and opening the device they name.
#pragma once
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <memory>
#include <string>

#include "megavox/build.h"
#include "megavox/device.h"

namespace mv::cli {

struct GlobalOptions {
  std::string device;         // --device / MEGAVOX_DEVICE
  std::string device_memory;  // --device-memory, e.g. 512M; empty = default
  bool profile = false;       // --profile
};

// Kernel compiles a cold cache makes: a notice and a progress line on stderr; nothing unless `enabled`.
CompileListener compile_notice(bool enabled);

// `quiet` (a command's --quiet): no compile notice, which otherwise shows when stderr is a terminal.
inline std::unique_ptr<Device> open_device(const GlobalOptions& g, bool quiet = false) {
  DeviceOptions o;
  o.selector = g.device;
  o.memory_budget = g.device_memory.empty() ? 0 : parse_size(g.device_memory);
  o.profile = g.profile;
  o.on_compile = compile_notice(!quiet && isatty(STDERR_FILENO));
  return Device::open(o);
}

// "X,Y,Z" -> three numbers; throws mv::Error naming the option (`what`) otherwise.
void parse_vec3(const std::string& text, const char* what, double out[3]);

// A progress bar: one line on stderr, redrawn in place; nothing unless `enabled` (a terminal, not --quiet).
Progress progress_bar(bool enabled);

// With --profile: the device time of each kernel since the last call, summed by name, on stderr.
void print_kernel_totals(Device& dev);

void add_devices_command(CLI::App& app, const GlobalOptions& g);
void add_bench_sort_command(CLI::App& bench, const GlobalOptions& g);
void add_build_command(CLI::App& app, const GlobalOptions& g);
void add_bench_build_command(CLI::App& bench, const GlobalOptions& g);
void add_bench_reductions_command(CLI::App& bench, const GlobalOptions& g);
void add_bench_trace_command(CLI::App& bench, const GlobalOptions& g);
void add_bench_points_command(CLI::App& bench, const GlobalOptions& g);
void add_bench_page_layout_command(CLI::App& bench);
void add_bench_cache_update_command(CLI::App& bench, const GlobalOptions& g);
void add_bench_cache_command(CLI::App& bench, const GlobalOptions& g);
void add_bench_mask_command(CLI::App& bench, const GlobalOptions& g);
void add_info_command(CLI::App& app);
void add_export_command(CLI::App& app, const GlobalOptions& g);
void add_import_command(CLI::App& app, const GlobalOptions& g);
void add_render_command(CLI::App& app, const GlobalOptions& g);
void add_points_command(CLI::App& app, const GlobalOptions& g);
void add_serve_command(CLI::App& app, const GlobalOptions& g);
void add_mask_command(CLI::App& app, const GlobalOptions& g);

}  // namespace mv::cli
