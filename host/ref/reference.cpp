#include "reference.h"

#include "../../kernels/common/voxelize.h"

#include <map>
#include <utility>

namespace mv::ref {

uint64_t morton3(uint32_t x, uint32_t y, uint32_t z, int bits_per_axis) {
  uint64_t key = 0;
  for (int i = 0; i < bits_per_axis; ++i) {
    key |= uint64_t{(x >> i) & 1u} << (3 * i);
    key |= uint64_t{(y >> i) & 1u} << (3 * i + 1);
    key |= uint64_t{(z >> i) & 1u} << (3 * i + 2);
  }
  return key;
}

std::vector<uint64_t> voxelize(const std::vector<float>& tris, uint32_t n) {
  std::vector<uint64_t> keys;
  for (size_t t = 0; t + 9 <= tris.size(); t += 9) {
    const float* v = &tris[t];
    uint32_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = mv_voxel_floor(std::min({double(v[a]), double(v[3 + a]), double(v[6 + a])}), n);
      hi[a] = mv_voxel_floor(std::max({double(v[a]), double(v[3 + a]), double(v[6 + a])}), n);
    }
    for (uint32_t x = lo[0]; x <= hi[0]; ++x)
      for (uint32_t y = lo[1]; y <= hi[1]; ++y)
        for (uint32_t z = lo[2]; z <= hi[2]; ++z)
          if (mv_voxel_hit(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], x, y, z, n))
            keys.push_back(morton3(x, y, z, 21));
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

DagCounts dag_counts(const std::vector<uint64_t>& voxels, uint32_t levels) {
  DagCounts out;
  out.svo.assign(levels + 1, 0);
  out.dag.assign(levels + 1, 0);
  out.svo[0] = out.dag[0] = voxels.size();
  std::map<uint64_t, uint32_t> below;  // key -> DAG id, one level down (voxels: all 0)
  for (uint64_t v : voxels) below[v] = 0;
  for (uint32_t l = 1; l <= levels; ++l) {
    using Node = std::pair<uint32_t, std::vector<uint32_t>>;  // (mask, child ids)
    std::map<uint64_t, Node> nodes;
    for (auto& [key, id] : below) {
      Node& n = nodes[key >> 3];
      n.first |= 1u << (key & 7);
      if (l > 1) n.second.push_back(id);
    }
    std::map<Node, uint32_t> distinct;
    std::map<uint64_t, uint32_t> ids;
    for (auto& [key, node] : nodes) ids[key] = distinct.emplace(node, uint32_t(distinct.size())).first->second;
    out.svo[l] = nodes.size();
    out.dag[l] = distinct.size();
    below = std::move(ids);
  }
  return out;
}

std::vector<uint32_t> exclusive_scan(const std::vector<uint32_t>& in) {
  std::vector<uint32_t> out(in.size() + 1, 0);
  for (size_t i = 0; i < in.size(); ++i) out[i + 1] = out[i] + in[i];
  return out;
}

}  // namespace mv::ref
