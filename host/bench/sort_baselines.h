// The CPU sorts `bench sort` compares megavox with, run on the same input and each checked against megavox's
// output (internal to the benchmark code).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "sort_bench.h"

namespace mv::bench {

// Sorts (input[i], i) records with every baseline built in, best of `repeats` each; `sorted` is megavox's
// sorted keys. A baseline that is not built in adds its missing_note() to `missing` instead of a run.
// SortBaselineRun::speedup is left to the caller, which knows megavox's time.
template <class Key>
std::vector<SortBaselineRun> run_sort_baselines(const std::vector<Key>& input, const std::vector<Key>& sorted,
                                                int repeats, std::vector<std::string>& missing);

}  // namespace mv::bench
