// `megavox bench page-layout`: how a DAG's node stream would page under each node order:
// size with padding, pointers that leave their page, pages a descent reads; level order is the baseline.
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <iostream>

#include "paging/page_layout.h"
#include "cli_common.h"
#include "megavox/mvx.h"

namespace mv::cli {

void add_bench_page_layout_command(CLI::App& bench) {
  struct Args {
    std::string file;
    std::vector<uint32_t> page_words = {1024, 4096, 16384};
    uint32_t paths = 100000;
    bool json = false;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = bench.add_subcommand(
      "page-layout",
      "Page a .mvx's node stream (svo, svdag, ussvdag) in level order (today's stream) and in subtree-clustered\n"
      "order (pages filled by breadth-first walks of subtrees), a node never split by a page: the paged size\n"
      "against the encoding's, the child pointers that leave their page, and the distinct pages a root-to-leaf\n"
      "descent reads (mean and max over --paths random descents, the same for both orders); then the ratio\n"
      "subtree / level. Host only.");
  cmd->add_option("file", a->file, "A voxel .mvx file")->required();
  cmd->add_option("--page-words", a->page_words, "Page sizes in 32-bit words")->delimiter(',')->capture_default_str();
  cmd->add_option("--paths", a->paths, "Random descents measured per layout")->capture_default_str();
  cmd->add_flag("--json", a->json, "Print one JSON object");
  cmd->callback([a] {
    const MvxFile f = read_mvx(a->file);
    nlohmann::json rows = nlohmann::json::array();
    if (!a->json)
      std::printf("%s: %s, %u levels, %llu words\n", a->file.c_str(), encoding_name(f.dag.encoding).c_str(),
                  f.dag.levels, (unsigned long long)f.dag.words.size());
    for (uint32_t pw : a->page_words) {
      PageLayoutStats s[2];
      double seconds[2];
      for (NodeOrder o : {NodeOrder::level, NodeOrder::subtree}) {
        const auto t0 = std::chrono::steady_clock::now();
        const PageLayout lay = page_layout(f.dag, o, pw);
        seconds[int(o)] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        s[int(o)] = measure_page_layout(f.dag, lay, a->paths, 1);
      }
      for (NodeOrder o : {NodeOrder::level, NodeOrder::subtree}) {
        const PageLayoutStats& r = s[int(o)];
        const double crossing = r.pointers ? double(r.crossing) / double(r.pointers) : 0;
        rows.push_back({{"order", node_order_name(o)}, {"page_words", pw}, {"pages", r.pages},
                        {"size_ratio", r.size_ratio}, {"crossing_pointers", crossing},
                        {"pages_per_path", r.pages_per_path}, {"max_pages_per_path", r.max_pages_per_path},
                        {"layout_seconds", seconds[int(o)]}});
        if (!a->json)
          std::printf("  %6u words/page %-7s: %8llu pages, size x%.4f, %5.1f %% of pointers leave their page, "
                      "%.2f pages per descent (max %u of %u levels), laid out in %.2f s\n",
                      pw, node_order_name(o).c_str(), (unsigned long long)r.pages, r.size_ratio, 100 * crossing,
                      r.pages_per_path, r.max_pages_per_path, r.levels, seconds[int(o)]);
      }
      if (!a->json)
        std::printf("  %6u words/page subtree / level: pages per descent %.3f\n", pw,
                    s[1].pages_per_path / s[0].pages_per_path);
    }
    if (a->json) {
      nlohmann::json j = {{"benchmark", "page-layout"}, {"file", a->file},
                          {"encoding", encoding_name(f.dag.encoding)}, {"levels", f.dag.levels},
                          {"words", f.dag.words.size()}, {"paths", a->paths}, {"layouts", rows}};
      std::cout << j.dump(2) << "\n";
    }
  });
}

}  // namespace mv::cli
