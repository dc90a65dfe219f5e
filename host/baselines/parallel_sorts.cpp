// The parallel CPU sort baselines that sort records by key: Boost.Sort's block_indirect_sort and ips4o's
// parallel samplesort (each present only when built in).
#include "baselines.h"

#if MEGAVOX_HAVE_BOOST_SORT
#include <boost/sort/sort.hpp>
#endif
#if MEGAVOX_HAVE_IPS4O
#include <ips4o.hpp>
#endif

namespace mv::baseline {

namespace {

enum class Library { boost, ips4o };

// Sorts by key with `lib` on all threads; false (the data left as it was) when that library is not built in.
template <class Pair>
bool sort_by_key(Library lib, [[maybe_unused]] std::span<Pair> pairs) {
  [[maybe_unused]] auto by_key = [](const Pair& a, const Pair& b) { return a.key < b.key; };
  if (lib == Library::boost) {
#if MEGAVOX_HAVE_BOOST_SORT
    boost::sort::block_indirect_sort(pairs.begin(), pairs.end(), by_key);
    return true;
#endif
  } else {
#if MEGAVOX_HAVE_IPS4O
    ips4o::parallel::sort(pairs.begin(), pairs.end(), by_key);
    return true;
#endif
  }
  return false;
}

}  // namespace

bool block_indirect_sort(std::span<Pair32> pairs) { return sort_by_key(Library::boost, pairs); }
bool block_indirect_sort(std::span<Pair64> pairs) { return sort_by_key(Library::boost, pairs); }
bool ips4o_parallel_sort(std::span<Pair32> pairs) { return sort_by_key(Library::ips4o, pairs); }
bool ips4o_parallel_sort(std::span<Pair64> pairs) { return sort_by_key(Library::ips4o, pairs); }

}  // namespace mv::baseline
