#include "point_gather.h"

#include <tbb/parallel_for.h>

#include <cstring>

#include "huge_pages.h"

namespace mv::points {

namespace {

template <class T, size_t K, class I>
void gather(const std::vector<T>& src, std::span<const I> index, std::vector<T>& out) {
  if (src.empty()) return;
  reserve_huge(out, index.size() * K);
  out.resize(index.size() * K);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, index.size(), 1 << 14), [&](const tbb::blocked_range<size_t>& r) {
    // Random reads: ask for the source of a point a few dozen ahead while this one is copied.
    constexpr size_t kAhead = 32;
    for (size_t i = r.begin(); i < r.end(); ++i) {
      if (i + kAhead < r.end()) __builtin_prefetch(&src[index[i + kAhead] * K]);
      for (size_t k = 0; k < K; ++k) out[i * K + k] = src[index[i] * K + k];
    }
  });
}

template <class I>
PointColumns gather_all(const PointColumns& src, std::span<const I> index, uint32_t extra_bytes) {
  PointColumns out;
  gather<int32_t, 3, I>(src.xyz, index, out.xyz);
  gather<uint16_t, 3, I>(src.rgb, index, out.rgb);
  gather<float, 3, I>(src.normal, index, out.normal);
  gather<uint16_t, 1, I>(src.intensity, index, out.intensity);
  if (!src.extra.empty() && extra_bytes) {
    out.extra.resize(index.size() * extra_bytes);
    tbb::parallel_for(size_t{0}, index.size(), [&](size_t i) {
      std::memcpy(&out.extra[i * extra_bytes], &src.extra[index[i] * extra_bytes], extra_bytes);
    });
  }
  return out;
}

}  // namespace

PointColumns gather_columns(const PointColumns& src, std::span<const uint64_t> index, uint32_t extra_bytes) {
  return gather_all(src, index, extra_bytes);
}

}  // namespace mv::points
