// `megavox bench sort`: radix sort on the device vs std::sort and the best parallel CPU sort, one run.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

#include "baselines.h"
#include "sort_bench.h"
#include "cli_common.h"
#include "megavox/error.h"

namespace mv::cli {

namespace {

struct BenchSortArgs {
  std::string n = "16M";
  int key_bits = 64;
  bool keys_only = false;
  int repeats = 5;
  std::string strategy = "auto";
  uint64_t seed = 1;
  bool json = false;
};

void print_table(const bench::SortBenchResult& r, const std::vector<KernelTiming>& totals) {
  std::printf("sort of %llu %s (%d-bit keys%s) on %s [%s]\n", static_cast<unsigned long long>(r.n),
              r.pairs ? "pairs" : "keys", r.key_bits, r.pairs ? ", 32-bit values" : "", r.device.name.c_str(),
              r.device.selector().c_str());
  std::printf("  %-36s %10s %14s %9s\n", "", "seconds", "keys/s", "ratio");
  std::printf("  %-36s %10.4f %14.3e %9s\n", "megavox radix sort (device-resident)", r.seconds, r.keys_per_s, "1.00");
  for (const auto& b : r.baselines)  // ratio: how many times faster megavox is
    std::printf("  %-36s %10.4f %14.3e %8.2fx%s\n", b.name.c_str(), b.seconds, b.keys_per_s, b.speedup,
                b.verified ? "" : "  (output WRONG)");
  std::printf("  variant %s, digit passes %u; upload %.4f s, download %.4f s; output %s\n", r.variant.c_str(),
              r.passes, r.upload_seconds,
              r.download_seconds, r.verified ? "verified (stable, a permutation of the input)" : "WRONG");
  const int pair = r.key_bits / 8 + (r.pairs ? 4 : 0);
  if (r.variant == "hybrid")
    std::printf("  floor: n x (%d B key read + 2 x 2 x %d B pair moves) / memcpy %.1f GB/s = %.4f s -> "
                "floor_fraction %.2f\n", r.key_bits / 8, pair, r.copy_gb_per_s, r.floor_seconds, r.floor_fraction);
  else
    std::printf("  floor: %u passes x 2 x n x %d B / memcpy %.1f GB/s = %.4f s -> floor_fraction %.2f\n", r.passes,
                pair, r.copy_gb_per_s, r.floor_seconds, r.floor_fraction);
  for (const auto& t : totals) std::printf("  kernel %-28s %10.4f s\n", t.kernel.c_str(), t.ns * 1e-9);
  for (const auto& m : r.missing_baselines) std::printf("  %s\n", m.c_str());
}

}  // namespace

void add_bench_sort_command(CLI::App& bench, const GlobalOptions& g) {
  auto args = std::make_shared<BenchSortArgs>();
  auto* cmd = bench.add_subcommand(
      "sort",
      "Stable radix sort of random keys (with their original index as value) on the device, against\n"
      "std::sort, tbb::parallel_sort, boost::sort::block_indirect_sort, ips4o::parallel::sort and\n"
      "vqsort (one thread) on the same data (each baseline that is built in; ratio = how many times\n"
      "faster megavox is), plus floor_fraction: the time memcpy would need to move the bytes the variant\n"
      "must move through memory (every LSD digit pass reads and writes each pair; the hybrid reads the\n"
      "keys once and moves each pair twice), over the measured time. Every output is checked in full.");
  cmd->add_option("--n", args->n, "Number of keys, e.g. 1M, 16M, 64M")->capture_default_str();
  cmd->add_option("--key-bits", args->key_bits, "Key width")->check(CLI::IsMember({32, 64}))->capture_default_str();
  cmd->add_flag("--keys-only", args->keys_only, "Sort keys without values");
  cmd->add_option("--repeats", args->repeats, "Runs of megavox and of each baseline; the best of each is reported")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  cmd->add_option("--strategy", args->strategy,
                  "Sort variant: auto (the device's choice), lsd, hybrid or cooperative (see docs/ARCHITECTURE.md)")
      ->check(CLI::IsMember({"auto", "lsd", "hybrid", "cooperative"}))
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "Seed of the random keys")->capture_default_str();
  cmd->add_flag("--json", args->json, "Print one JSON object instead of the table");
  cmd->callback([&g, args] {
    auto dev = open_device(g);
    bench::SortBenchOptions o;
    o.n = parse_size(args->n);
    o.key_bits = args->key_bits;
    o.pairs = !args->keys_only;
    o.repeats = args->repeats;
    o.strategy = args->strategy == "lsd"           ? SortStrategy::Lsd
                 : args->strategy == "hybrid"      ? SortStrategy::Hybrid
                 : args->strategy == "cooperative" ? SortStrategy::Cooperative
                                                   : SortStrategy::Auto;
    o.seed = args->seed;
    bench::SortBenchResult r = bench::run_sort_bench(*dev, o);
    if (args->json) {
      nlohmann::json kernels = nlohmann::json::object();
      for (const auto& t : r.kernel_totals) kernels[t.kernel] = t.ns * 1e-9;
      nlohmann::json baselines = nlohmann::json::array();
      for (const auto& b : r.baselines)
        baselines.push_back({{"name", b.name},
                             {"seconds", b.seconds},
                             {"keys_per_s", b.keys_per_s},
                             {"speedup", b.speedup},
                             {"verified", b.verified}});
      // The peers to beat, by name (null when not built in).
      auto field = [&](const std::string& name, double bench::SortBaselineRun::*f) {
        const bench::SortBaselineRun* b = r.baseline(name);
        return b ? nlohmann::json(b->*f) : nlohmann::json(nullptr);
      };
      const std::string ips4o = baseline::ips4o().name, vqsort = baseline::vqsort().name;
      nlohmann::json j = {{"benchmark", "sort"},
                          {"device", r.device.name},
                          {"device_selector", r.device.selector()},
                          {"backend", r.device.backend},
                          {"n", r.n},
                          {"key_bits", r.key_bits},
                          {"pairs", r.pairs},
                          {"passes", r.passes},
                          {"variant", r.variant},
                          {"seconds", r.seconds},
                          {"upload_seconds", r.upload_seconds},
                          {"download_seconds", r.download_seconds},
                          {"keys_per_s", r.keys_per_s},
                          {"std_sort_seconds", r.std_sort_seconds},
                          {"std_sort_keys_per_s", r.std_sort_keys_per_s},
                          {"parallel_sort", r.parallel_sort_name},
                          {"parallel_sort_seconds", r.parallel_sort_seconds},
                          {"parallel_sort_keys_per_s", r.parallel_sort_keys_per_s},
                          {"speedup_vs_std_sort", r.speedup_vs_std_sort},
                          {"speedup_vs_parallel_sort", r.speedup_vs_parallel_sort},
                          {"ips4o_keys_per_s", field(ips4o, &bench::SortBaselineRun::keys_per_s)},
                          {"speedup_vs_ips4o", field(ips4o, &bench::SortBaselineRun::speedup)},
                          {"vqsort_keys_per_s", field(vqsort, &bench::SortBaselineRun::keys_per_s)},
                          {"speedup_vs_vqsort", field(vqsort, &bench::SortBaselineRun::speedup)},
                          {"baselines", baselines},
                          {"copy_gb_per_s", r.copy_gb_per_s},
                          {"floor_bytes", r.floor_bytes},
                          {"floor_seconds", r.floor_seconds},
                          {"floor_fraction", r.floor_fraction},
                          {"verified", r.verified},
                          {"missing_baselines", r.missing_baselines},
                          {"kernel_seconds", kernels}};
      std::cout << j.dump(2) << "\n";
    } else {
      print_table(r, r.kernel_totals);
    }
    if (!r.verified) throw mv::Error("bench sort: the device output is not the stable sort of the input");
    for (const auto& b : r.baselines)
      if (!b.verified) throw mv::Error("bench sort: " + b.name + "'s output differs from megavox's sort");
  });
}

}  // namespace mv::cli
