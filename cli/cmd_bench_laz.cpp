// `megavox bench laz FILE...`: LAZ decoding speed, all threads and one, against laz-perf (LASzip compiled to
// WebAssembly, the decoder a web viewer uses) running in node on the same file.
#include <nlohmann/json.hpp>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <thread>

#include "cli_common.h"
#include "io/las_convert.h"
#include "megavox/error.h"

namespace mv::cli {

namespace {

struct LazPerf {
  double points_per_second = 0;
  std::string missing;  // why there is no figure
};

std::string quoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// laz-perf's decode alone (node's start-up and the WebAssembly instantiation excluded), best of `repeats`.
LazPerf run_lazperf(const std::string& dir, const std::string& file, unsigned repeats, uint64_t points) {
  LazPerf r;
  namespace fs = std::filesystem;
  if (!fs::exists(dir + "/laz_decode.mjs") || !fs::exists(dir + "/node_modules/laz-perf")) {
    r.missing = "no laz-perf in " + dir + " (scripts/setup.sh installs it with npm ci; --lazperf DIR names another)";
    return r;
  }
  const std::string command = "node " + quoted(dir + "/laz_decode.mjs") + " " + quoted(file) +
                              " --no-output --repeats " + std::to_string(repeats) + " 2>&1";
  std::FILE* p = ::popen(command.c_str(), "r");
  if (!p) {
    r.missing = "cannot run node";
    return r;
  }
  std::string out;
  char buf[4096];
  for (size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
  const int status = ::pclose(p);
  try {
    if (status != 0) throw std::runtime_error(out);
    const nlohmann::json j = nlohmann::json::parse(out.substr(out.rfind('{')));
    const double seconds = j.at("seconds").get<double>();
    if (j.at("points").get<uint64_t>() != points) throw std::runtime_error("it decoded another number of points");
    r.points_per_second = seconds > 0 ? points / seconds : 0;
  } catch (const std::exception& e) {
    // node's own error line (the one naming what failed), not its stack.
    std::string what = e.what(), line;
    for (size_t at = 0; at < what.size();) {
      const size_t end = std::min(what.find('\n', at), what.size());
      const std::string l = what.substr(at, end - at);
      if (line.empty() || l.find("Error") != std::string::npos) line = l;
      if (l.find("Error") != std::string::npos) break;
      at = end + 1;
    }
    r.missing = "laz-perf failed: " + line;
  }
  return r;
}

double best_seconds(const std::string& file, unsigned threads, unsigned repeats, io::LasConvertReport* report) {
  double best = 1e300;
  for (unsigned i = 0; i < repeats; ++i) {
    *report = io::decode_las_points(file, threads);
    best = std::min(best, report->decode_seconds);
  }
  return best;
}

}  // namespace

void add_bench_laz_command(CLI::App& bench) {
  struct Args {
    std::vector<std::string> files;
    std::string lazperf = "tests/js";
    unsigned repeats = 3;
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = bench.add_subcommand(
      "laz",
      "LAZ decoding: every point of each file decompressed into memory, with every hardware thread (chunks in\n"
      "parallel) and with one, best of --repeats; beside laz-perf (LASzip in WebAssembly) decoding the same file\n"
      "in node, its decode alone timed. laz-perf is found in --lazperf DIR (tests/js, installed by\n"
      "scripts/setup.sh); without it its field is absent and one line says why.\n"
      "Example: megavox bench laz ../shared/data/pointcloud_laz/autzen_trim.laz --json");
  cmd->add_option("files", a->files, "LAZ (or LAS) files")->required();
  cmd->add_option("--repeats", a->repeats, "Runs per figure; the best is reported (default 3)");
  cmd->add_option("--lazperf", a->lazperf, "The folder holding laz_decode.mjs and node_modules/laz-perf");
  cmd->add_flag("--json", a->json, "One JSON object per file, one per line");
  cmd->callback([a] {
    if (a->repeats == 0) throw Error("--repeats must be at least 1");
    const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
    if (!a->json)
      std::printf("%-40s %10s %12s %12s %12s %8s\n", "file", "points", "M pts/s", "1 thread", "laz-perf", "1t/lp");
    for (const std::string& file : a->files) {
      io::LasConvertReport report;
      const double all = best_seconds(file, 0, a->repeats, &report);
      const double one = best_seconds(file, 1, a->repeats, &report);
      const LazPerf lp = run_lazperf(a->lazperf, file, a->repeats, report.points);
      const double pps = report.points / all, pps1 = report.points / one;
      if (a->json) {
        nlohmann::json j = {{"benchmark", "laz"},
                            {"file", file},
                            {"format", report.input_format},
                            {"points", report.points},
                            {"threads", hw},
                            {"points_per_second", pps},
                            {"points_per_second_1thread", pps1},
                            {"repeats", a->repeats}};
        if (lp.missing.empty()) {
          j["lazperf_points_per_second"] = lp.points_per_second;
          j["ratio_1thread_to_lazperf"] = pps1 / lp.points_per_second;
        } else {
          j["lazperf_missing"] = lp.missing;
        }
        std::cout << j.dump() << std::endl;
        continue;
      }
      const std::string name = std::filesystem::path(file).filename().string();
      if (lp.missing.empty())
        std::printf("%-40s %10llu %12.2f %12.2f %12.2f %8.2f\n", name.c_str(), (unsigned long long)report.points,
                    pps / 1e6, pps1 / 1e6, lp.points_per_second / 1e6, pps1 / lp.points_per_second);
      else
        std::printf("%-40s %10llu %12.2f %12.2f %12s %8s\n  laz-perf: %s\n", name.c_str(),
                    (unsigned long long)report.points, pps / 1e6, pps1 / 1e6, "-", "-", lp.missing.c_str());
    }
  });
}

}  // namespace mv::cli
