// `megavox bench build --ranks N` and `bench points --ranks N`: the same build under `mpirun -np 1` and `mpirun -np N` on this machine only
// (shared memory and loopback), timed from outside, their outputs compared.
#pragma once
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "cli_common.h"

namespace mv::cli {

struct RanksBench {
  std::string status = "ran";  // or one line saying why it did not run
  int ranks = 0;
  double one_rank_seconds = 0, seconds = 0;  // best of the repeats, mpirun's start included in both
  bool same_bytes = false;
  nlohmann::json report;  // rank 0's `--json` of the N-rank run (its `ranks`, `merge_share`)
};

// `build` is the verb and its options, without -o (`build MESH ...`, `points build CLOUD ...`); the global
// options (--device, --device-memory, --kernel-shape) go to every rank.
RanksBench bench_ranks(const std::vector<std::string>& build, const GlobalOptions& g, int ranks, int repeats);

// `verb` then `args`.
std::vector<std::string> with_verb(std::vector<std::string> verb, const std::vector<std::string>& args);

nlohmann::json ranks_json(const RanksBench& b);
void print_ranks_bench(const RanksBench& b);

}  // namespace mv::cli
