// Dealing weighted items to ranks in contiguous ranges, and the sums that deal by (megavox/rank_collectives.h).
#include <algorithm>

#include "megavox/error.h"
#include "megavox/rank_collectives.h"
#include "megavox/rank_message.h"

namespace mv {

std::vector<uint64_t> sum_over_ranks(const RankCollectives& ranks, const std::vector<uint64_t>& values) {
  MessageWriter mine;
  mine.put_all(values);
  std::vector<uint64_t> sums(values.size(), 0), theirs;
  for (const std::vector<uint8_t>& b : ranks.all_gather(mine.bytes)) {
    MessageReader(b).get_all(theirs);
    if (theirs.size() != sums.size()) throw Error("internal error: the ranks sum lists of different lengths");
    for (size_t i = 0; i < sums.size(); ++i) sums[i] += theirs[i];
  }
  return sums;
}

std::vector<int> deal_in_order(const std::vector<uint64_t>& weights, int ranks) {
  uint64_t total = 0;
  for (uint64_t w : weights) total += w;
  std::vector<int> owner(weights.size(), 0);
  uint64_t before = 0;  // weight of the items before this one
  for (size_t i = 0; i < weights.size(); ++i) {
    // the rank whose equal share holds this item's first unit: contiguous ranges in order
    const uint64_t r = total == 0 ? 0 : static_cast<uint64_t>((unsigned __int128)before * ranks / total);
    owner[i] = static_cast<int>(std::min<uint64_t>(r, ranks - 1));
    before += weights[i];
  }
  return owner;
}

}  // namespace mv
