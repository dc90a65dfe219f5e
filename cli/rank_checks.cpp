#include "rank_checks.h"

#include <fstream>
#include <vector>

#include "megavox/error.h"
#include "megavox/ranks.h"

namespace mv::cli {

void check_every_rank_reads(const std::string& input) {
  if (dist::world().size <= 1) return;
  const std::vector<int> blind = dist::ranks_failing(std::ifstream(input, std::ios::binary).good());
  if (blind.empty()) return;
  std::string names;
  for (int r : blind) names += (names.empty() ? "" : ", ") + std::to_string(r);
  throw IoError(input + ": rank" + (blind.size() > 1 ? "s " : " ") + names +
                " cannot read it, and every rank reads the input; nothing was built");
}

}  // namespace mv::cli
