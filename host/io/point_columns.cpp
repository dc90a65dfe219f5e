#include "megavox/points.h"

namespace mv {

void PointColumns::clear() {
  xyz.clear();
  rgb.clear();
  normal.clear();
  intensity.clear();
  extra.clear();
}

void PointColumns::append(const PointColumns& from, uint64_t i, uint32_t extra_bytes) {
  xyz.insert(xyz.end(), from.xyz.begin() + 3 * i, from.xyz.begin() + 3 * i + 3);
  if (!from.rgb.empty()) rgb.insert(rgb.end(), from.rgb.begin() + 3 * i, from.rgb.begin() + 3 * i + 3);
  if (!from.normal.empty()) normal.insert(normal.end(), from.normal.begin() + 3 * i, from.normal.begin() + 3 * i + 3);
  if (!from.intensity.empty()) intensity.push_back(from.intensity[i]);
  if (!from.extra.empty() && extra_bytes)
    extra.insert(extra.end(), from.extra.begin() + i * extra_bytes, from.extra.begin() + (i + 1) * extra_bytes);
}

}  // namespace mv
