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

// Records of `record_bytes` bytes: out record i = src record index[i].
template <class I>
void gather_bytes(const uint8_t* src, uint32_t record_bytes, std::span<const I> index, uint8_t* out) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, index.size(), 1 << 14), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i)
      std::memcpy(out + i * record_bytes, src + uint64_t{index[i]} * record_bytes, record_bytes);
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
    gather_bytes<I>(src.extra.data(), extra_bytes, index, out.extra.data());
  }
  return out;
}

// Node k's points go to out[offset[k] * K...]: a leaf's as one block, an inner node's one representative at a time.
template <class T, size_t K>
void gather_nodes(const std::vector<T>& src, std::span<const NodePoints> sources, std::span<const uint64_t> offset,
                  std::span<const uint64_t> reps, std::vector<T>& out) {
  if (src.empty()) return;
  const uint64_t total = offset.back();
  reserve_huge(out, total * K);
  out.resize(total * K);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, sources.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k < r.end(); ++k) {
      const NodePoints& s = sources[k];
      T* dst = out.data() + offset[k] * K;
      if (!s.reps) {
        std::memcpy(dst, src.data() + s.first * K, uint64_t{s.count} * K * sizeof(T));
        continue;
      }
      const uint64_t* idx = reps.data() + s.first;
      constexpr uint32_t kAhead = 16;
      for (uint32_t i = 0; i < s.count; ++i) {
        if (i + kAhead < s.count) __builtin_prefetch(&src[idx[i + kAhead] * K]);
        for (size_t c = 0; c < K; ++c) dst[i * K + c] = src[idx[i] * K + c];
      }
    }
  });
}

}  // namespace

PointColumns gather_node_points(const PointColumns& sorted, std::span<const NodePoints> sources,
                                std::span<const uint64_t> reps, uint32_t extra_bytes) {
  std::vector<uint64_t> offset(sources.size() + 1, 0);
  for (size_t k = 0; k < sources.size(); ++k) offset[k + 1] = offset[k] + sources[k].count;
  PointColumns out;
  gather_nodes<int32_t, 3>(sorted.xyz, sources, offset, reps, out.xyz);
  gather_nodes<uint16_t, 3>(sorted.rgb, sources, offset, reps, out.rgb);
  gather_nodes<float, 3>(sorted.normal, sources, offset, reps, out.normal);
  gather_nodes<uint16_t, 1>(sorted.intensity, sources, offset, reps, out.intensity);
  if (!sorted.extra.empty() && extra_bytes) {
    // Whole records of extra_bytes bytes: the same walk over bytes, a record's bytes together.
    out.extra.resize(offset.back() * extra_bytes);
    tbb::parallel_for(size_t{0}, sources.size(), [&](size_t k) {
      const NodePoints& s = sources[k];
      for (uint32_t i = 0; i < s.count; ++i) {
        const uint64_t q = s.reps ? reps[s.first + i] : s.first + i;
        std::memcpy(&out.extra[(offset[k] + i) * extra_bytes], &sorted.extra[q * extra_bytes], extra_bytes);
      }
    });
  }
  return out;
}

PointColumns gather_columns(const PointColumns& src, std::span<const uint64_t> index, uint32_t extra_bytes) {
  return gather_all(src, index, extra_bytes);
}
PointColumns gather_columns(const PointColumns& src, std::span<const uint32_t> index, uint32_t extra_bytes) {
  return gather_all(src, index, extra_bytes);
}

void gather_record_bytes(const uint8_t* src, uint32_t record_bytes, std::span<const uint32_t> index, uint8_t* out) {
  gather_bytes<uint32_t>(src, record_bytes, index, out);
}

}  // namespace mv::points
