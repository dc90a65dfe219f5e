// `megavox bench cache-update`: the page cache's data-parallel update pass per pass against a CPU LRU.
#include <nlohmann/json.hpp>

#include <cstdio>
#include <iostream>

#include "cache_bench.h"
#include "cli_common.h"

namespace mv::cli {

void add_bench_cache_update_command(CLI::App& bench, const GlobalOptions& g) {
  struct Args {
    bench::CacheBenchConfig c;
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = bench.add_subcommand(
      "cache-update",
      "Time the page cache's update pass (LRU partition, request list, eviction, placement: kernels and the\n"
      "host's waits) per pass on the device, against a classic CPU LRU (a list of slots moved on every use) fed\n"
      "the same kind of passes in the same run: a view of --view consecutive pages drifting --drift pages a\n"
      "pass. Defaults: 16 MiB of 16 KiB slots over koala's 16K^3 svdag in 16 KiB pages. The traversal's stamp\n"
      "writes are stood in for by uploads (not timed); producing a page is a copy from host memory.");
  cmd->add_option("--slots", a->c.slots, "Cache slots")->capture_default_str();
  cmd->add_option("--pages", a->c.pages, "Page ids")->capture_default_str();
  cmd->add_option("--page-words", a->c.page_words, "32-bit words per page")->capture_default_str();
  cmd->add_option("--passes", a->c.passes, "Passes (one update each)")->capture_default_str();
  cmd->add_option("--view", a->c.view, "Pages one pass needs")->capture_default_str();
  cmd->add_option("--drift", a->c.drift, "Pages the view moves per pass")->capture_default_str();
  cmd->add_flag("--json", a->json, "Print one JSON object");
  cmd->callback([&g, a] {
    auto dev = open_device(g);
    const bench::CacheBenchConfig& c = a->c;
    const bench::CacheBenchResult r = bench::run_cache_bench(*dev, c);
    if (g.profile) print_kernel_totals(*dev);
    if (a->json) {
      nlohmann::json j = {{"benchmark", "cache-update"}, {"device", dev->info().name}, {"slots", c.slots},
                          {"pages", c.pages}, {"page_words", c.page_words}, {"passes", c.passes},
                          {"view", c.view}, {"drift", c.drift}, {"device_manage_ms", r.device_manage_ms},
                          {"device_produce_ms", r.device_produce_ms}, {"cpu_lru_ms", r.cpu_lru_ms},
                          {"ratio", r.ratio}, {"device_hit_rate", r.device_hit_rate},
                          {"cpu_hit_rate", r.cpu_hit_rate}, {"loads", r.loads}, {"evictions", r.evictions},
                          {"bytes_uploaded", r.bytes_uploaded}};
      std::cout << j.dump(2) << "\n";
      return;
    }
    std::printf("page cache update on %s: %u slots of %u words over %u pages, %u passes, view %u drifting %u\n",
                dev->info().name.c_str(), c.slots, c.page_words, c.pages, c.passes, c.view, c.drift);
    std::printf("  device update %.3f ms per pass (producing and uploading pages %.3f ms apart); CPU LRU %.3f ms;"
                " device / CPU %.2f\n",
                r.device_manage_ms, r.device_produce_ms, r.cpu_lru_ms, r.ratio);
    std::printf("  hit rate %.4f (CPU LRU %.4f); %llu loads, %llu evictions, %.1f MB uploaded\n", r.device_hit_rate,
                r.cpu_hit_rate, (unsigned long long)r.loads, (unsigned long long)r.evictions, r.bytes_uploaded / 1e6);
  });
}

}  // namespace mv::cli
