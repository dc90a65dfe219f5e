#include "bench_ranks.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "scratch_dir.h"

namespace mv::cli {

namespace {

std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string self_path() {
  std::error_code ec;
  const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? "megavox" : p.string();
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// One mpirun of the build; its wall seconds. Throws mv::Error with what it printed when it fails.
double run_once(const std::string& command, const std::string& log) {
  const auto t = std::chrono::steady_clock::now();
  const int rc = std::system((command + " > " + quoted(log) + " 2> " + quoted(log + ".err")).c_str());
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  if (rc != 0) throw Error("mpirun failed: " + slurp(log + ".err") + slurp(log));
  return s;
}

}  // namespace

RanksBench bench_ranks(const std::vector<std::string>& build, const GlobalOptions& g, int ranks, int repeats) {
  RanksBench b;
  b.ranks = ranks;
  if (std::system("command -v mpirun > /dev/null 2>&1") != 0)
    return {"ranks: not run: no mpirun (scripts/setup.sh installs openmpi-bin)"};
  if (dist::mpi_summary().rfind("not built in", 0) == 0) return {"ranks: not run: megavox is built without MPI"};
  bench::ScratchDir scratch;
  // This machine only: shared memory and loopback, never another interface; ranks may outnumber cores, and are
  // not bound to one core each (Open MPI binds 1 or 2 ranks to a core each, leaving a lone rank one core).
  std::string env = "OMPI_MCA_btl=self,vader OMPI_MCA_oob_tcp_if_include=lo OMPI_MCA_btl_tcp_if_include=lo "
                    "OMPI_MCA_rmaps_base_oversubscribe=1 OMPI_MCA_hwloc_base_binding_policy=none ";
  if (geteuid() == 0) env += "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ";
  std::string global = quoted(self_path());
  if (!g.device.empty()) global += " --device " + quoted(g.device);
  if (!g.device_memory.empty()) global += " --device-memory " + quoted(g.device_memory);
  if (!g.kernel_shape.empty()) global += " --kernel-shape " + quoted(g.kernel_shape);
  std::string args;
  for (const std::string& a : build) args += " " + quoted(a);
  auto command = [&](int n, const std::string& out) {
    return env + "mpirun -np " + std::to_string(n) + " " + global + args + " -q --json -o " + quoted(out);
  };
  const std::string one = scratch.file("one.mvx"), many = scratch.file("many.mvx"), log = scratch.file("log");
  try {
    for (int r = 0; r < repeats; ++r) {
      const double s1 = run_once(command(1, one), log);
      const double sn = run_once(command(ranks, many), log);
      if (r == 0 || s1 < b.one_rank_seconds) b.one_rank_seconds = s1;
      if (r == 0 || sn < b.seconds) b.seconds = sn, b.report = nlohmann::json::parse(slurp(log));
    }
  } catch (const std::exception& e) {
    return {std::string("ranks: ") + e.what()};
  }
  std::ifstream x(one, std::ios::binary), y(many, std::ios::binary);
  b.same_bytes = std::string(std::istreambuf_iterator<char>(x), {}) == std::string(std::istreambuf_iterator<char>(y), {});
  return b;
}

std::vector<std::string> with_verb(std::vector<std::string> verb, const std::vector<std::string>& args) {
  verb.insert(verb.end(), args.begin(), args.end());
  return verb;
}

nlohmann::json ranks_json(const RanksBench& b) {
  if (b.status != "ran") return {{"status", b.status}};
  return {{"ranks", b.ranks},
          {"one_rank_seconds", b.one_rank_seconds},
          {"seconds", b.seconds},
          {"speedup", b.seconds > 0 ? b.one_rank_seconds / b.seconds : 0},
          {"same_bytes", b.same_bytes},
          {"per_rank", b.report.value("ranks", nlohmann::json::array())},
          {"merge_share", b.report.value("merge_share", 0.0)}};
}

void print_ranks_bench(const RanksBench& b) {
  if (b.status != "ran") {
    std::printf("  %s\n", b.status.c_str());
    return;
  }
  std::printf("  over MPI: 1 rank %.3f s, %d ranks %.3f s (speed-up %.2fx, mpirun's start in both), %s bytes\n",
              b.one_rank_seconds, b.ranks, b.seconds, b.seconds > 0 ? b.one_rank_seconds / b.seconds : 0.0,
              b.same_bytes ? "the same" : "DIFFERENT");
}

}  // namespace mv::cli
