#include "reference.h"

#include "common/voxelize.h"

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

std::vector<uint64_t> voxelize(const std::vector<float>& tris, uint32_t n, bool thin) {
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
          if (mv_voxel_hit(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], x, y, z, n, thin ? 1u : 0u))
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

namespace {

uint32_t reflect(uint32_t mask, uint32_t t) {
  uint32_t r = 0;
  for (uint32_t c = 0; c < 8; ++c)
    if (mask >> c & 1) r |= 1u << (c ^ t);
  return r;
}

uint32_t normalize(uint32_t tag, uint32_t stab) {
  uint32_t best = tag;
  for (uint32_t s = 0; s < 8; ++s)
    if (stab >> s & 1) best = std::min(best, tag ^ s);
  return best;
}

}  // namespace

DagCounts ssvdag_counts(const std::vector<uint64_t>& voxels, uint32_t levels) {
  DagCounts out;
  out.svo.assign(levels + 1, 0);
  out.dag.assign(levels + 1, 0);
  out.svo[0] = out.dag[0] = voxels.size();
  struct Ref {
    uint32_t id, tag;
  };
  std::map<uint64_t, Ref> below;  // node key -> (class id, tag) one level down
  std::vector<uint32_t> stab_below;
  for (uint64_t v : voxels) below[v] = {0, 0};
  for (uint32_t l = 1; l <= levels; ++l) {
    struct Node {
      uint32_t mask = 0;
      Ref child[8] = {};
    };
    std::map<uint64_t, Node> nodes;
    for (auto& [key, ref] : below) {
      Node& n = nodes[key >> 3];
      n.mask |= 1u << (key & 7);
      n.child[key & 7] = ref;
    }
    std::map<std::vector<uint64_t>, uint32_t> classes;
    std::vector<uint32_t> stab_here;
    std::map<uint64_t, Ref> refs;
    for (auto& entry : nodes) {
      const auto& key = entry.first;
      auto& n = entry.second;  // a plain reference: clang 14 cannot capture a structured binding
      auto key_of = [&](uint32_t t) {
        std::vector<uint64_t> k{reflect(n.mask, t)};
        if (l > 1)
          for (uint32_t o = 0; o < 8; ++o) {
            uint32_t c = o ^ t;
            k.push_back(n.mask >> c & 1
                            ? (uint64_t{n.child[c].id} << 3 | normalize(n.child[c].tag ^ t, stab_below[n.child[c].id]))
                            : 0);
          }
        return k;
      };
      uint32_t best = 0, stab = 0;
      for (uint32_t t = 0; t < 8; ++t) {
        if (key_of(t) < key_of(best)) best = t;
        if (key_of(t) == key_of(0)) stab |= 1u << t;
      }
      auto [it, fresh] = classes.emplace(key_of(best), uint32_t(classes.size()));
      if (fresh) stab_here.push_back(stab);
      refs[key] = {it->second, normalize(best, stab)};
    }
    out.svo[l] = nodes.size();
    out.dag[l] = classes.size();
    below = std::move(refs);
    stab_below = std::move(stab_here);
  }
  return out;
}

std::vector<uint32_t> exclusive_scan(const std::vector<uint32_t>& in) {
  std::vector<uint32_t> out(in.size() + 1, 0);
  for (size_t i = 0; i < in.size(); ++i) out[i + 1] = out[i] + in[i];
  return out;
}

std::vector<uint64_t> exclusive_scan64(const std::vector<uint32_t>& in, uint64_t start) {
  std::vector<uint64_t> out(in.size() + 1, start);
  for (size_t i = 0; i < in.size(); ++i) out[i + 1] = out[i] + in[i];
  return out;
}

std::vector<uint64_t> unique_sorted(const std::vector<uint64_t>& sorted) {
  std::vector<uint64_t> out;
  for (uint64_t k : sorted)
    if (out.empty() || out.back() != k) out.push_back(k);
  return out;
}

}  // namespace mv::ref
