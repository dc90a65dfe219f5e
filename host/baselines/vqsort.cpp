// The vectorized quicksort baseline: Highway's vqsort through hwy::Sorter, the entry points Debian's
// libhwy_contrib exports (present only when built in). It picks its SIMD target at run time.
#include "baselines.h"

#if MEGAVOX_HAVE_VQSORT
#include <hwy/contrib/sort/vqsort.h>

#include <type_traits>
#endif

namespace mv::baseline {

namespace {
#if MEGAVOX_HAVE_VQSORT
hwy::Sorter& sorter() {
  static thread_local hwy::Sorter s;  // made once, so its buffer is not allocated inside a timing
  return s;
}
#endif

template <class Key>
bool sort_keys(std::span<Key> keys) {
#if MEGAVOX_HAVE_VQSORT
  if constexpr (std::is_same_v<Key, U128>) {
    static_assert(sizeof(U128) == sizeof(hwy::uint128_t) && alignof(U128) >= alignof(hwy::uint128_t));
    sorter()(reinterpret_cast<hwy::uint128_t*>(keys.data()), keys.size(), hwy::SortAscending());
  } else {
    sorter()(keys.data(), keys.size(), hwy::SortAscending());
  }
  return true;
#else
  (void)keys;
  return false;
#endif
}
}  // namespace

bool vqsort(std::span<uint32_t> keys) { return sort_keys(keys); }
bool vqsort(std::span<uint64_t> keys) { return sort_keys(keys); }
bool vqsort(std::span<U128> keys) { return sort_keys(keys); }

}  // namespace mv::baseline
