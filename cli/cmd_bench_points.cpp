// `megavox bench points`: `megavox points build` timed on point clouds (files, and one sampled from a mesh by the
// benchmark itself), beside the floor of megavox's own reader and a plain read of each file.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "points_bench.h"
#include "scratch_dir.h"
#include "stopwatch.h"
#include "bench_ranks.h"
#include "cli_common.h"
#include "profile_report.h"
#include "megavox/error.h"

namespace mv::cli {

namespace {

struct BenchPointsArgs {
  std::vector<std::string> inputs;
  std::string sample_mesh, sample_points = "100M", keep_sample, memory;
  uint64_t seed = 1;
  int repeats = 3, sample_repeats = 1;
  uint32_t max_node_points = 16384;
  uint32_t sort_ranges = PointBuildOptions().sort_ranges;
  int ranks = 0;
  bool json = false, quiet = false;
};

const char* kPotreeStatus =
    "PotreeConverter: not run (not packaged in Debian); vs_potree_quoted = points_per_second / 2.85 M points/s, "
    "a published PotreeConverter 2 rate on a comparable machine, not measured in this run";

struct Cloud {
  bench::PointsBenchResult r;
  std::optional<bench::MeshSample> sample;
  int repeats = 1;
};

double mib(uint64_t bytes) { return double(bytes) / (1 << 20); }

std::string label(const Cloud& c) {
  if (c.sample)
    return std::filesystem::path(c.sample->mesh).filename().string() + " sampled, " +
           std::to_string(c.sample->points) + " points";
  return std::filesystem::path(c.r.input).filename().string();
}

void print_runs(const std::vector<double>& runs) {
  std::printf("best of %zu:", runs.size());
  for (double s : runs) std::printf(" %.4f", s);
}

void print_cloud(const Cloud& c) {
  const bench::PointsBenchResult& r = c.r;
  const PointFileReport& p = r.report;
  std::printf("%s (%s)\n", c.sample ? label(c).c_str() : r.input.c_str(), p.input_format.c_str());
  if (c.sample)
    std::printf("  sampled from %s: %llu triangles, area %.6g, seed %llu, %.1f MiB written in %.2f s (not in the "
                "figures)%s%s\n",
                c.sample->mesh.c_str(), (unsigned long long)c.sample->triangles, c.sample->area,
                (unsigned long long)c.sample->seed, mib(c.sample->bytes), c.sample->seconds,
                r.input.empty() ? "" : "; file ", r.input.c_str());
  std::printf("  points in %llu, kept %llu, dropped %llu; %llu nodes, depth %u, %llu points stored\n",
              (unsigned long long)p.points_in, (unsigned long long)p.points_kept,
              (unsigned long long)p.points_dropped, (unsigned long long)p.nodes, p.depth,
              (unsigned long long)p.stored_points);
  std::printf("  read floor (open_points + next() to the end) %.4f s = %.2f M points/s (", r.floor.seconds,
              r.floor_points_per_second * 1e-6);
  print_runs(r.floor_runs);
  std::printf("); plain read %.4f s (%.2f GB/s); read into growing columns %.4f s (%.2fx the floor)\n",
              r.plain.seconds, r.plain.gb_per_s(), r.stored.seconds,
              r.floor.seconds > 0 ? r.stored.seconds / r.floor.seconds : 0);
  std::printf("  read + sort + build %.4f s = %.2f M points/s (", r.seconds, r.points_per_second * 1e-6);
  print_runs(r.build_runs);
  std::printf("): read %.3f, sort %.3f (codes %.3f + sort %.3f), build %.3f (build %.3f + gather %.3f); write "
              "%.3f, %.3f s with it\n",
              p.read_seconds, p.sort_seconds, p.build.codes_seconds, p.build.sort_seconds, p.build_seconds,
              p.build.build_seconds, p.build.gather_seconds, p.write_seconds, r.seconds_with_write);
  const Parallelism& q = r.parallelism;
  std::printf("  parallelism (best build, read to write): device %.4f s, host %.4f s, waiting %.4f s, file I/O %.4f "
              "s; narrow dispatches (under %llu work-items) %.4f s = %.1f %% of the device's\n",
              q.device_seconds, q.host_seconds, q.wait_seconds, q.io_seconds, (unsigned long long)q.width,
              q.narrow_seconds, q.device_seconds > 0 ? 100 * q.narrow_seconds / q.device_seconds : 0.0);
  std::printf("  build / read floor %.2fx; peak RSS %.1f MiB (%s); vs PotreeConverter 2's published 2.85 M "
              "points/s (not measured here) %.2fx\n",
              r.ratio_to_read_floor, mib(r.peak_rss_bytes),
              r.peak_rss_reset ? "this cloud's runs" : "the process's so far", r.vs_potree_quoted);
}

void print_summary(const std::vector<Cloud>& clouds) {
  std::printf("\n| cloud | points | read floor s | floor M pts/s | plain read s | read+sort+build s | M pts/s | "
              "build / floor | read | sort | build | write | nodes | depth | stored | peak RSS MiB | "
              "vs potree (published) |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const Cloud& c : clouds) {
    const auto& r = c.r;
    const auto& p = r.report;
    std::printf("| %s | %llu | %.4f | %.2f | %.4f | %.4f | %.2f | %.2f | %.4f | %.4f | %.4f | %.4f | %llu | %u | "
                "%llu | %.0f | %.2f |\n",
                label(c).c_str(), (unsigned long long)p.points_in, r.floor.seconds,
                r.floor_points_per_second * 1e-6, r.plain.seconds, r.seconds, r.points_per_second * 1e-6,
                r.ratio_to_read_floor, p.read_seconds, p.sort_seconds, p.build_seconds, p.write_seconds,
                (unsigned long long)p.nodes, p.depth, (unsigned long long)p.stored_points, mib(r.peak_rss_bytes),
                r.vs_potree_quoted);
  }
}

nlohmann::json cloud_json(const Cloud& c, const DeviceInfo& device, double open_seconds, double warmup_seconds) {
  const bench::PointsBenchResult& r = c.r;
  const PointFileReport& p = r.report;
  nlohmann::json sample = nullptr;
  if (c.sample)
    sample = {{"mesh", c.sample->mesh},       {"points", c.sample->points}, {"triangles", c.sample->triangles},
              {"area", c.sample->area},       {"seed", c.sample->seed},     {"bytes", c.sample->bytes},
              {"seconds", c.sample->seconds}, {"path", c.sample->path}};
  return {{"benchmark", "points"},
          {"device", device.name},
          {"selector", device.selector()},
          {"input", r.input},
          {"input_format", p.input_format},
          {"sample", sample},
          {"repeats", c.repeats},
          {"points", p.points_in},
          {"points_kept", p.points_kept},
          {"points_dropped", p.points_dropped},
          {"stored_points", p.stored_points},
          {"nodes", p.nodes},
          {"depth", p.depth},
          {"nodes_per_level", p.nodes_per_level},
          {"points_per_second", r.points_per_second},
          {"read_floor_seconds", r.floor.seconds},
          {"read_floor_seconds_runs", r.floor_runs},
          {"read_floor_points", r.floor.points},
          {"read_floor_points_per_second", r.floor_points_per_second},
          {"read_store_seconds", r.stored.seconds},
          {"plain_read_seconds", r.plain.seconds},
          {"plain_read_bytes", r.plain.bytes},
          {"plain_read_gb_per_s", r.plain.gb_per_s()},
          {"seconds", {{"read", p.read_seconds}, {"sort", p.sort_seconds}, {"build", p.build_seconds},
                       {"write", p.write_seconds}}},
          {"stages_seconds", {{"read", p.read_seconds}, {"codes", p.build.codes_seconds},
                              {"sort", p.build.sort_seconds}, {"build", p.build.build_seconds},
                              {"gather", p.build.gather_seconds}, {"write", p.write_seconds}}},
          {"total_seconds", r.seconds},
          {"total_seconds_runs", r.build_runs},
          {"total_with_write_seconds", r.seconds_with_write},
          {"wall_seconds", p.total_seconds},
          {"ratio_to_read_floor", r.ratio_to_read_floor},
          {"peak_rss_bytes", r.peak_rss_bytes},
          {"peak_rss_reset", r.peak_rss_reset},
          {"vs_potree_quoted", r.vs_potree_quoted},
          {"potree_quoted_points_per_second", bench::kPotreeQuotedPointsPerSecond},
          {"potree_status", kPotreeStatus},
          {"sort_runs", p.build.sort.runs},
          {"steps", p.build.steps},
          {"parallelism", parallelism_json(r.parallelism)},
          {"kernel_shape", device.massively_parallel ? "gpu" : "cpu"},
          {"device_open_seconds", open_seconds},
          {"warmup_seconds", warmup_seconds}};
}

}  // namespace

void add_bench_points_command(CLI::App& bench, const GlobalOptions& g) {
  auto a = std::make_shared<BenchPointsArgs>();
  auto* cmd = bench.add_subcommand(
      "points",
      "Time `megavox points build` (read, sort, build; the .mvx write apart) on point clouds, best of --repeats,\n"
      "beside its floor: megavox's reader decoding every point and nothing else (open_points + next() to the\n"
      "end), the same reader appending to growing columns as points build's read stage does, and a plain read\n"
      "of the file. With --sample-mesh the benchmark also samples --sample-points points\n"
      "from a triangle mesh's surface (area-weighted, fixed seed, colour from the face normal) into a scratch\n"
      "binary PLY and times that cloud too. Prints points/s, the ratio to the read floor, nodes, depth and peak\n"
      "RSS per cloud; PotreeConverter is not run (not in Debian): it is compared by its published 2.85 M points/s.\n"
      "Each cloud also reports the parallelism profile of its best build, read to write (`parallelism`: device,\n"
      "host, waiting and file I/O seconds, the device time of dispatches narrower than the device, per kernel\n"
      "launches, work-items and seconds; --profile also lists the kernels on stderr; see docs/runtime.md).\n"
      "--json prints one JSON object per cloud, one per line. Example:\n"
      "  megavox bench points scan.las cloud.ply --sample-mesh igea.ply --sample-points 100M --json");
  cmd->add_option("input", a->inputs, "Point clouds (.ply, .las)");
  cmd->add_option("--sample-mesh", a->sample_mesh, "A triangle mesh (PLY, OBJ, ...) to sample a cloud from");
  cmd->add_option("--sample-points", a->sample_points, "Points to sample, e.g. 200K, 100M, 1G (binary units)")
      ->capture_default_str();
  cmd->add_option("--seed", a->seed, "Seed of the sampling")->capture_default_str();
  cmd->add_option("--keep-sample", a->keep_sample, "Write the sampled cloud here and keep it (default: scratch)");
  cmd->add_option("--repeats", a->repeats, "Read floors and builds of each input file; the best is reported")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  cmd->add_option("--sample-repeats", a->sample_repeats, "The same for the sampled cloud")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  cmd->add_option("--max-node-points", a->max_node_points, "As points build's (default 16384)");
  cmd->add_option("--sort-ranges", a->sort_ranges,
                  "Ranges of buckets the in-place sort hands the builder while it sorts (1: after the sort)")
      ->capture_default_str();
  cmd->add_option("--memory", a->memory, "As points build's: host budget, e.g. 16G (default: half the RAM)");
  cmd->add_option("--ranks", a->ranks,
                  "Also build each cloud under `mpirun -np 1` and `mpirun -np N` (this machine only: shared memory\n"
                  "and loopback), and report the speed-up of N ranks over one and whether the bytes are the same")
      ->check(CLI::Range(2, 256));
  cmd->add_flag("--json", a->json, "One JSON object per cloud (one a line) instead of the tables");
  cmd->add_flag("-q,--quiet", a->quiet, "No progress lines on stderr");
  cmd->callback([&g, a] {
    if (a->inputs.empty() && a->sample_mesh.empty())
      throw Error("bench points: give point clouds, --sample-mesh MESH, or both");
    const uint64_t sample_points = parse_size(a->sample_points);
    if (!a->sample_mesh.empty() && sample_points == 0) throw Error("bench points: --sample-points must be above 0");
    auto note = [&](const std::string& line) {
      if (!a->quiet) std::fprintf(stderr, "bench points: %s\n", line.c_str());
    };
    PointBuildOptions build;
    build.max_node_points = a->max_node_points;
    build.sort_ranges = std::max(1u, a->sort_ranges);
    const uint64_t memory = a->memory.empty() ? 0 : parse_size(a->memory);

    const auto t = bench::Clock::now();
    auto dev = open_device(g, false, true);  // profiled always: each cloud reports its parallelism
    const double open_seconds = bench::since(t);
    const double warmup_seconds = bench::warm_up_point_build(*dev, build);
    note("device " + dev->info().name + " opened in " + std::to_string(open_seconds) + " s, kernels warmed up in " +
         std::to_string(warmup_seconds) + " s");

    std::vector<Cloud> clouds;
    auto run = [&](const std::string& path, int repeats, std::optional<bench::MeshSample> sample) {
      note("timing " + path + " (" + std::to_string(repeats) + " repeats)");
      Cloud c;
      c.r = bench::run_points_bench(*dev, path, repeats, build, memory);
      if (sample && sample->path.empty()) c.r.input.clear();  // a scratch file, removed
      c.sample = std::move(sample);
      c.repeats = repeats;
      if (g.profile && !a->json) print_parallelism(label(c) + " (best build, read to write)", c.r.parallelism);
      std::optional<RanksBench> ranks;
      if (a->ranks > 1) {
        note("building " + path + " over 1 and " + std::to_string(a->ranks) + " ranks");
        std::vector<std::string> args{"points", "build", path, "--max-node-points", std::to_string(a->max_node_points)};
        if (!a->memory.empty()) args.insert(args.end(), {"--memory", a->memory});
        ranks = bench_ranks(args, g, a->ranks, repeats);
      }
      if (a->json) {
        nlohmann::json j = cloud_json(c, dev->info(), open_seconds, warmup_seconds);
        if (ranks) j["ranks"] = ranks_json(*ranks);
        std::cout << j.dump() << std::endl;
      } else {
        print_cloud(c);
        if (ranks) print_ranks_bench(*ranks);
      }
      clouds.push_back(std::move(c));
    };
    for (const std::string& input : a->inputs) run(input, a->repeats, std::nullopt);
    if (!a->sample_mesh.empty()) {
      std::optional<bench::ScratchDir> scratch;
      std::string path = a->keep_sample;
      if (path.empty()) {
        scratch.emplace();
        path = scratch->file(std::filesystem::path(a->sample_mesh).stem().string() + "_" + a->sample_points + ".ply");
      }
      note("sampling " + std::to_string(sample_points) + " points from " + a->sample_mesh + " into " + path);
      bench::MeshSample s = bench::sample_mesh_to_ply(a->sample_mesh, sample_points, path, a->seed);
      note("sampled in " + std::to_string(s.seconds) + " s");
      if (a->keep_sample.empty()) s.path.clear();  // removed with the scratch folder
      run(path, a->sample_repeats, s);
    }
    if (!a->json) {
      print_summary(clouds);
      std::printf("\n%s\n", kPotreeStatus);
    }
  });
}

}  // namespace mv::cli
