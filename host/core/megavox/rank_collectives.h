// megavox — what a build spread over several processes (MPI ranks) asks of them: a few collectives over byte
// buffers, which host/dist implements over MPI (megavox/ranks.h), and a fair deal of weighted items to ranks.
// The core calls them and never names MPI.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

namespace mv {

using RankBytes = std::vector<std::vector<uint8_t>>;  // one buffer per rank, in rank order

struct RankCollectives {
  int rank = 0, size = 1;
  // Every rank's buffer, on every rank.
  std::function<RankBytes(const std::vector<uint8_t>& mine)> all_gather;
  // parts[r] goes to rank r; returns what each rank sent to this one.
  std::function<RankBytes(RankBytes&& parts)> all_to_all;
  // Every rank's buffer at rank 0; the others get an empty list.
  std::function<RankBytes(std::vector<uint8_t>&& mine)> gather;
  // Called on rank 0 once the others only wait for it (they sleep): it may take every core of the node.
  std::function<void()> lead_alone;
  // A barrier whose waiting ranks sleep: for the other ranks to wait out rank 0's work alone.
  std::function<void()> sleepy_barrier;
};

// The bytes of the buffers for (or from) ranks other than `self`: what an exchange moves between processes.
inline uint64_t bytes_of_others(const RankBytes& parts, int self) {
  uint64_t n = 0;
  for (size_t r = 0; r < parts.size(); ++r)
    if (static_cast<int>(r) != self) n += parts[r].size();
  return n;
}

// Collective: the element-wise sums of every rank's `values` (the same length on every rank), added in rank
// order, on every rank.
std::vector<uint64_t> sum_over_ranks(const RankCollectives& ranks, const std::vector<uint64_t>& values);

// Which rank gets each item of a sequence: contiguous ranges in its order, each about total / ranks of the
// weights (an item goes to the rank whose equal share holds its first unit of weight).
std::vector<int> deal_in_order(const std::vector<uint64_t>& weights, int ranks);

}  // namespace mv
