// Flat-DDA reference traversal (see trace_reference.h).
#include "trace_reference.h"

#include <algorithm>

#include "reference.h"

namespace mv::ref {

Occupancy::Occupancy(const std::vector<uint64_t>& voxels, uint32_t levels) : levels_(levels), keys_(levels + 1) {
  for (uint32_t l = 0; l <= levels; ++l) {
    auto& k = keys_[l];
    k.reserve(voxels.size());
    for (uint64_t v : voxels) k.push_back(v >> (3 * l));
    std::sort(k.begin(), k.end());
    k.erase(std::unique(k.begin(), k.end()), k.end());
  }
}

bool Occupancy::full(uint32_t level, uint32_t x, uint32_t y, uint32_t z) const {
  return std::binary_search(keys_[level].begin(), keys_[level].end(), morton3(x, y, z, 21));
}

namespace {

// Voxel index along axis k where the ray is just after event (te, ae): every voxel boundary of the axis it
// crossed by that event (mv_crossed) has moved it one voxel on. Boundaries are crossed in order, so the
// crossed ones form a prefix: binary search for its length.
uint32_t entry_voxel(float o, float inv, uint32_t k, float te, uint32_t ae, uint32_t n, float side) {
  const bool pos = inv > 0.0f;
  if (k == ae) return pos ? 0 : n - 1;
  auto crossed = [&](uint32_t c) {  // the c-th boundary met along the direction of travel (c = 1..n-1)
    uint32_t b = pos ? c : n - c;
    return mv_crossed(mv_cross(float(b) * side, o, inv), k, te, ae);
  };
  uint32_t lo = 0, hi = n - 1;  // the count is in [lo, hi]
  while (lo < hi) {
    uint32_t mid = (lo + hi + 1) / 2;
    if (crossed(mid)) lo = mid;
    else hi = mid - 1;
  }
  return pos ? lo : n - 1 - lo;
}

}  // namespace

MvHit trace(const Occupancy& occ, const MvRay& ray, float proj) {
  const uint32_t L = occ.levels();
  MvHit h{};
  h.info = MV_TRACE_MISS | (MV_AXIS_NONE << 2);
  const float o[3] = {ray.ox, ray.oy, ray.oz};
  const float inv[3] = {mv_rcp(mv_dir_clamp(ray.dx)), mv_rcp(mv_dir_clamp(ray.dy)), mv_rcp(mv_dir_clamp(ray.dz))};
  MvEntry e = mv_ray_entry(o[0], o[1], o[2], inv[0], inv[1], inv[2], ray.tmax);
  if (!e.enters) return h;
  const uint32_t n = 1u << L;
  const float voxel = mv_cell_side(0, L);
  uint32_t idx[3];
  for (uint32_t k = 0; k < 3; ++k) idx[k] = entry_voxel(o[k], inv[k], k, e.t, e.axis, n, voxel);
  // When and across which axis the ray entered the cell of each level it is in.
  std::vector<float> t_in(L + 1, e.t);
  std::vector<uint32_t> axis_in(L + 1, e.axis);
  for (uint32_t steps = 1;; ++steps) {
    for (int l = int(L) - 1; l >= 0; --l) {
      uint32_t cx = idx[0] >> l, cy = idx[1] >> l, cz = idx[2] >> l;
      if (!occ.full(uint32_t(l), cx, cy, cz)) break;
      if (l == 0 || (proj > 0.0f && mv_cell_side(uint32_t(l), L) * proj < t_in[l] + ray.lod_t)) {
        h.t = t_in[l];
        h.x = cx;
        h.y = cy;
        h.z = cz;
        uint32_t a = axis_in[l];
        uint32_t negative = a != MV_AXIS_NONE && inv[a] > 0.0f ? 1u : 0u;
        h.info = MV_TRACE_HIT | (a << 2) | (negative << 4) | (uint32_t(l) << 8);
        h.steps = steps;
        return h;
      }
    }
    // Next voxel: the earliest boundary crossing, lowest axis on equal times.
    uint32_t a = 0;
    float ta = 0;
    for (uint32_t k = 0; k < 3; ++k) {
      float t = mv_cross(float(idx[k] + (inv[k] > 0.0f ? 1u : 0u)) * voxel, o[k], inv[k]);
      if (k == 0 || t < ta) {
        ta = t;
        a = k;
      }
    }
    if (ta > ray.tmax) return h;
    uint32_t next = inv[a] > 0.0f ? idx[a] + 1 : idx[a] - 1;
    if (next >= n) return h;
    for (uint32_t l = 0; l < L; ++l)
      if ((next >> l) != (idx[a] >> l)) {
        t_in[l] = ta;
        axis_in[l] = a;
      }
    idx[a] = next;
  }
}

}  // namespace mv::ref
