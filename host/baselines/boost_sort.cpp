// The parallel CPU sort baseline: Boost.Sort's block_indirect_sort (present only when built in).
#include "baselines/baselines.h"

#if MEGAVOX_HAVE_BOOST_SORT
#include <boost/sort/sort.hpp>
#endif

namespace mv::baseline {

namespace {
template <class Pair>
bool sort_by_key(std::span<Pair> pairs) {
#if MEGAVOX_HAVE_BOOST_SORT
  boost::sort::block_indirect_sort(pairs.begin(), pairs.end(),
                                   [](const Pair& a, const Pair& b) { return a.key < b.key; });
  return true;
#else
  (void)pairs;
  return false;
#endif
}
}  // namespace

bool block_indirect_sort(std::span<Pair32> pairs) { return sort_by_key(pairs); }
bool block_indirect_sort(std::span<Pair64> pairs) { return sort_by_key(pairs); }

}  // namespace mv::baseline
