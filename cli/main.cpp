// megavox command line: parses, reports, and leaves the work to the host pipelines.
#include <cstdlib>
#include <cstdio>
#include <iostream>
#include <map>
#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli_common.h"
#include "error_flags.h"
#include "suggest.h"
#include "megavox/error.h"

namespace mv::cli {
void parse_vec3(const std::string& text, const char* what, double out[3]) {
  std::istringstream in(text);
  char c1 = 0, c2 = 0;
  if (!(in >> out[0] >> c1 >> out[1] >> c2 >> out[2]) || c1 != ',' || c2 != ',' || !in.eof())
    throw CodedError(ErrorCode::invalid_argument,
                     std::string(what) + " wants X,Y,Z (three numbers separated by commas), got '" + text + "'");
}

std::array<double, 6> parse_bounds(const std::string& text) {
  std::istringstream in(text);
  std::array<double, 6> b{};
  bool ok = true;
  for (int i = 0; i < 6 && ok; ++i) {
    char comma = ',';
    ok = static_cast<bool>(in >> b[i]) && std::isfinite(b[i]);
    if (ok && i < 5) ok = static_cast<bool>(in >> comma) && comma == ',';
  }
  ok = ok && in.eof();
  for (int a = 0; a < 3 && ok; ++a) ok = b[a] <= b[3 + a];
  if (!ok)
    throw CodedError(ErrorCode::invalid_argument,
                     "--bounds wants MINX,MINY,MINZ,MAXX,MAXY,MAXZ (six numbers, each min at most its max), got '" +
                         text + "'");
  return b;
}

// One line on stderr, redrawn in place; only on a terminal.
Progress progress_bar(bool enabled) {
  if (!enabled) return {};
  return [last = std::string()](const std::string& stage, double f) mutable {
    const int width = 30;
    int filled = static_cast<int>(f * width + 0.5);
    std::fprintf(stderr, "\r%-9s [%s%s] %3.0f%%", stage.c_str(), std::string(filled, '#').c_str(),
                 std::string(width - filled, ' ').c_str(), 100 * f);
    if (stage != last && !last.empty()) std::fprintf(stderr, "\n");
    last = stage;
    std::fflush(stderr);
  };
}

void print_kernel_totals(Device& dev) {
  std::map<std::string, std::pair<uint64_t, uint64_t>> totals;  // name -> (ns, dispatches)
  for (const auto& t : dev.take_timings()) {
    if (std::getenv("MV_EACH")) std::fprintf(stderr, "  %s %.4f\n", t.kernel.c_str(), t.ns * 1e-9);
    totals[t.kernel].first += t.ns;
    totals[t.kernel].second += 1;
  }
  for (const auto& [name, v] : totals)
    std::fprintf(stderr, "kernel %-24s %10.4f s %8llu dispatches\n", name.c_str(), v.first * 1e-9,
                 (unsigned long long)v.second);
}
// The command line, in one process or as one rank of an MPI run; the exit status.
int run(int argc, char** argv, const dist::World& world);

}  // namespace mv::cli

int main(int argc, char** argv) {
  const mv::dist::World& world = mv::dist::start(&argc, &argv);  // MPI only under mpirun
  const int code = mv::cli::run(argc, argv, world);
  if (code != 0 && world.size > 1) mv::dist::abort_all(code);  // mpirun ends every rank, with this one's message
  mv::dist::stop();
  return code;
}

int mv::cli::run(int argc, char** argv, const mv::dist::World& world) {
  CLI::App app{
      "megavox: a compute backend for massive 3D models (sparse voxel octrees and DAGs, point hierarchies)\n"
      "on any OpenCL or Vulkan compute device, CPU or GPU.\n\n"
      "Examples:\n"
      "  megavox devices                       list the compute devices megavox can use\n"
      "  megavox build bunny.ply --resolution 4K -o bunny.mvx   voxelize a mesh into a voxel DAG\n"
      "  megavox info bunny.mvx                validate a .mvx file and print what it holds\n"
      "  megavox points build scan.las -o scan.mvx   an LOD point hierarchy (or --format 3dtiles -o DIR)\n"
      "  megavox mask apply photo.jpg --rect 40,30,300,200 -o masks/   a GrabCut mask of a photograph\n"
      "  megavox bench sort --n 16M            radix-sort 16M (key, value) pairs and compare with std::sort\n"
      "  megavox --device vk:0 bench sort      the same on the first Vulkan device\n"
      "  megavox serve --listen 127.0.0.1:0    an HTTP compute service (jobs, progress, ray queries)\n"
      "  MEGAVOX_DEVICE=pocl megavox devices   pick a device by (part of) its name\n",
      "megavox"};
  app.set_version_flag("--version", std::string("megavox ") + MEGAVOX_VERSION + "\nMPI: " + mv::dist::mpi_summary());
  app.require_subcommand(1);
  app.fallthrough();

  mv::cli::GlobalOptions g;
  app.add_option("--device", g.device,
                 "Device to run on: ocl:N (OpenCL devices across platforms), vk:N (Vulkan devices), or part of a "
                 "device or platform name such as pocl or llvmpipe. Default: $MEGAVOX_DEVICE, else a GPU "
                 "(Vulkan first), else PoCL")
      ->envname("MEGAVOX_DEVICE");
  app.add_option("--device-memory", g.device_memory,
                 "Device memory budget, e.g. 512M or 2G (default: 3/4 of what the device reports). Work that "
                 "does not fit fails with a message naming what it needs");
  app.add_flag("--profile", g.profile,
               "Time every kernel on the device. The verbs that run a pipeline (build, points build, mask apply)\n"
               "print its parallelism profile (on stderr; inside the JSON with --json): wall, host, waiting and\n"
               "file I/O seconds, device seconds, narrow seconds (dispatches with fewer work-items than the\n"
               "device runs at once: compute units x preferred work-group size x 4), and per kernel its\n"
               "launches, work-items and seconds; other verbs print the kernels' totals");
  app.add_option("--kernel-shape", g.kernel_shape,
                 "How kernels are launched: gpu (wide grids, cooperative variants, work-groups of 64), cpu (a\n"
                 "block of items per work-item), or auto (by the device's type; the default). Every shape gives\n"
                 "the same bytes; `megavox devices --json` shows the shape in effect. Default: "
                 "$MEGAVOX_KERNEL_SHAPE, else auto")
      ->envname("MEGAVOX_KERNEL_SHAPE")
      ->check(CLI::IsMember({"auto", "gpu", "cpu"}));

  mv::cli::add_devices_command(app, g);
  mv::cli::add_build_command(app, g);
  mv::cli::add_info_command(app);
  mv::cli::add_render_command(app, g);
  mv::cli::add_points_command(app, g);
  mv::cli::add_mask_command(app, g);
  mv::cli::add_export_command(app, g);
  mv::cli::add_import_command(app, g);
  mv::cli::add_serve_command(app, g);
  CLI::App* bench = app.add_subcommand("bench", "Measure megavox against the tools a user would pick instead");
  bench->require_subcommand(1);
  mv::cli::add_bench_sort_command(*bench, g);
  mv::cli::add_bench_build_command(*bench, g);
  mv::cli::add_bench_reductions_command(*bench, g);
  mv::cli::add_bench_trace_command(*bench, g);
  mv::cli::add_bench_points_command(*bench, g);
  mv::cli::add_bench_page_layout_command(*bench);
  mv::cli::add_bench_cache_update_command(*bench, g);
  mv::cli::add_bench_cache_command(*bench, g);
  mv::cli::add_bench_attributes_command(*bench, g);
  mv::cli::add_bench_mask_command(*bench, g);
  mv::cli::add_bench_laz_command(*bench);

  // With --json anywhere on the line, a failure is one JSON object on stdout, like the verb's output would be.
  bool json = false;
  for (int i = 1; i < argc; ++i) json = json || std::string(argv[i]) == "--json";
  // Under mpirun every rank's message names the rank.
  const std::string who = world.size > 1 ? "rank " + std::to_string(world.rank) + " of " + std::to_string(world.size) + ": " : "";
  auto fail = [json, &who](mv::ErrorCode code, const std::string& message) {
    if (json) std::cout << nlohmann::json{{"error", who + message}, {"code", mv::error_code_name(code)}}.dump() << std::endl;
    else std::fprintf(stderr, "megavox: %s%s: %s\n", who.c_str(), code == mv::ErrorCode::unknown ? "internal error" : "error",
                      message.c_str());
  };
  if (world.size > 1) {  // only a build is spread over ranks: any other verb would run N times over
    std::string verb;
    for (int i = 1; i < argc && verb.empty(); ++i)
      for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
        if (sub->get_name() == argv[i]) verb = argv[i];
    // `points build` too: the word after `points` names its verb
    bool points_build = false;
    for (int i = 1; i + 1 < argc; ++i)
      if (std::string(argv[i]) == "points") points_build = std::string(argv[i + 1]) == "build";
    if (verb != "build" && !(verb == "points" && points_build)) {
      fail(mv::ErrorCode::invalid_argument, "`megavox " + (verb.empty() ? std::string("...") : verb) +
                                                "` runs in one process; under mpirun only `megavox build` and "
                                                "`megavox points build` run, spread over the ranks");
      return 1;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0 || dynamic_cast<const CLI::CallForHelp*>(&e) ||
        dynamic_cast<const CLI::CallForAllHelp*>(&e) || dynamic_cast<const CLI::CallForVersion*>(&e))
      return app.exit(e);
    fail(mv::ErrorCode::invalid_argument, mv::cli::diagnose_unknown_word(app, argc, argv).value_or(e.what()));
    return e.get_exit_code();
  } catch (const std::exception& e) {
    const mv::ErrorCode code = mv::classify(e);
    fail(code, mv::cli::message_with_flags(e));
    return code == mv::ErrorCode::unknown ? 2 : 1;
  }
  return 0;
}
