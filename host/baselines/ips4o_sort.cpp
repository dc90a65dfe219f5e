// The in-place parallel samplesort baseline: ips4o::parallel::sort (present only when built in).
#include "baselines/baselines.h"

#if MEGAVOX_HAVE_IPS4O
#include <ips4o.hpp>
#endif

namespace mv::baseline {

namespace {
template <class Pair>
bool sort_by_key(std::span<Pair> pairs) {
#if MEGAVOX_HAVE_IPS4O
  ips4o::parallel::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.key < b.key; });
  return true;
#else
  (void)pairs;
  return false;
#endif
}
}  // namespace

bool ips4o_parallel_sort(std::span<Pair32> pairs) { return sort_by_key(pairs); }
bool ips4o_parallel_sort(std::span<Pair64> pairs) { return sort_by_key(pairs); }

}  // namespace mv::baseline
