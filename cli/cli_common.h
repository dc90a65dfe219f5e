// What every megavox subcommand shares: the global options and opening the device they name.
#pragma once
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <memory>
#include <array>
#include <string>

#include "megavox/ranks.h"
#include "megavox/build.h"
#include "megavox/device.h"
#include "megavox/error.h"
#include "megavox/min_cut.h"

namespace mv::cli {

struct GlobalOptions {
  std::string device;         // --device / MEGAVOX_DEVICE
  std::string device_memory;  // --device-memory, e.g. 512M; empty = default
  bool profile = false;       // --profile
  std::string kernel_shape;   // --kernel-shape / MEGAVOX_KERNEL_SHAPE: auto, gpu, cpu; empty = auto
};

// --kernel-shape as a KernelShape; throws mv::CodedError (invalid_argument) for another word.
inline KernelShape kernel_shape(const GlobalOptions& g) {
  return g.kernel_shape.empty() ? KernelShape::automatic : parse_kernel_shape(g.kernel_shape);
}

// Runs `body`; an mv::Error it throws that says nothing of its kind (not coded, memory, I/O or device) comes out as
// `code`: what a step's failures mean is known where the step is taken (a bad option value, no such device).
template <class F>
auto with_code(ErrorCode code, F&& body) {
  try {
    return body();
  } catch (const CodedError&) {
    throw;
  } catch (const DeviceMemoryError&) {
    throw;
  } catch (const IoError&) {
    throw;
  } catch (const DeviceError&) {
    throw;
  } catch (const Error& e) {
    throw CodedError(code, e.what(), e.settings);
  }
}

// Kernel compiles a cold cache makes: a notice and a progress line on stderr; nothing unless `enabled`.
CompileListener compile_notice(bool enabled);

// `quiet` (a command's --quiet): no compile notice, which otherwise shows when stderr is a terminal. `profile`:
// time the kernels even without --profile (the benchmarks that always report a parallelism profile).
inline std::unique_ptr<Device> open_device(const GlobalOptions& g, bool quiet = false, bool profile = false) {
  DeviceOptions o;
  o.selector = g.device;
  o.memory_budget = g.device_memory.empty() ? 0 : with_code(ErrorCode::invalid_argument, [&] {
    return parse_size(g.device_memory);
  });
  o.profile = g.profile || profile;
  o.budget_share = static_cast<uint32_t>(dist::world().local_size);  // ranks on this node share the device
  o.kernel_shape = kernel_shape(g);
  o.on_compile = compile_notice(!quiet && isatty(STDERR_FILENO));
  return with_code(ErrorCode::unsupported_device, [&] { return Device::open(o); });
}

// "X,Y,Z" -> three numbers; throws mv::Error naming the option (`what`) otherwise.
void parse_vec3(const std::string& text, const char* what, double out[3]);

// --bounds "MINX,MINY,MINZ,MAXX,MAXY,MAXZ" (world units) -> the box; throws mv::Error saying the form otherwise.
std::array<double, 6> parse_bounds(const std::string& text);

// --no-clobber: refuse to replace an existing output (inputs, devices and FIFOs are always refused).
inline CLI::Option* add_no_clobber_flag(CLI::App& cmd, bool& flag) {
  return cmd.add_flag("--no-clobber", flag, "Refuse to replace an output that exists already");
}

// The image format a picture's name asks for: "jpeg" for .jpg / .jpeg, else "png" (write_image's rule).
std::string image_format(const std::string& path);

// A progress bar: one line on stderr, redrawn in place; nothing unless `enabled` (a terminal, not --quiet).
Progress progress_bar(bool enabled);

// With --profile: the device time of each kernel since the last call, summed by name, on stderr.
void print_kernel_totals(Device& dev);

// --min-cut-solver auto|regions|push-relabel into `name` (mask apply, bench mask; cmd_mask.cpp); min_cut_solver()
// turns the checked name into the solver.
CLI::Option* add_min_cut_solver_option(CLI::App& cmd, std::string& name);
MinCutSolver min_cut_solver(const std::string& name);

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
void add_bench_attributes_command(CLI::App& bench, const GlobalOptions& g);
void add_bench_mask_command(CLI::App& bench, const GlobalOptions& g);
void add_bench_laz_command(CLI::App& bench);
void add_points_convert(CLI::App& points);
void add_info_command(CLI::App& app);
void add_export_command(CLI::App& app, const GlobalOptions& g);
void add_import_command(CLI::App& app, const GlobalOptions& g);
void add_render_command(CLI::App& app, const GlobalOptions& g);
void add_points_command(CLI::App& app, const GlobalOptions& g);
void add_serve_command(CLI::App& app, const GlobalOptions& g);
void add_mask_command(CLI::App& app, const GlobalOptions& g);

}  // namespace mv::cli
