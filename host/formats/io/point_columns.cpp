// PointColumns (megavox/points.h): the column operations readers and the LOD builder share.
#include "megavox/points.h"

#include <algorithm>

#include "huge_pages.h"

namespace mv {

namespace {

template <class T>
void grow(std::vector<T>& v, uint64_t need) {
  if (need > v.capacity()) reserve_huge(v, std::max<uint64_t>(need, 2 * v.capacity()));
}

}  // namespace

void PointColumns::reserve_more(uint64_t more, uint32_t attributes, uint32_t extra_bytes) {
  const uint64_t total = size() + more;
  grow(xyz, 3 * total);
  if (attributes & kPointRgb) grow(rgb, 3 * total);
  if (attributes & kPointNormal) grow(normal, 3 * total);
  if (attributes & kPointIntensity) grow(intensity, total);
  if ((attributes & kPointExtra) && extra_bytes) grow(extra, uint64_t{extra_bytes} * total);
}

void PointColumns::clear() {
  xyz.clear();
  rgb.clear();
  normal.clear();
  intensity.clear();
  extra.clear();
}

void PointColumns::append(const PointColumns& from, uint64_t i, uint32_t extra_bytes) {
  // A column is copied when `from` carries it: its columns are either empty or hold every point.
  auto copy = [i](auto& to, const auto& src, uint64_t per_point) {
    if (src.empty()) return;
    auto first = src.begin() + static_cast<std::ptrdiff_t>(i * per_point);
    to.insert(to.end(), first, first + static_cast<std::ptrdiff_t>(per_point));
  };
  copy(xyz, from.xyz, 3);
  copy(rgb, from.rgb, 3);
  copy(normal, from.normal, 3);
  copy(intensity, from.intensity, 1);
  if (extra_bytes > 0) copy(extra, from.extra, extra_bytes);
}

}  // namespace mv
