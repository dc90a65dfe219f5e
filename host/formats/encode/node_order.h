// The ssvdag's node orders, computed from a DAG's shape alone, so that the encoder (encode_ssvdag) and the paged
// ssvdag's way back (host/formats/paging/paged_ssvdag.cpp) agree without a stored permutation. Levels 2 .. L (2: the
// bricks), node 0 of level L the root. `count(l)`: the nodes of level l; `children(l, k, f)`: calls
// f(Morton octant, child) for each child of node k of level l >= 3, in any order.
#pragma once
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

namespace mv {

// Each level's nodes in the order a walk from the root first meets them: level by level, parents in that order,
// children by ascending Morton octant (close in space); nodes never met (none in a reduced DAG) follow in index
// order.
template <class Count, class Children>
std::vector<std::vector<uint32_t>> first_met_order(uint32_t L, Count&& count, Children&& children) {
  std::vector<std::vector<uint32_t>> seen(L + 1);
  seen[L].push_back(0);
  for (uint32_t l = L; l >= 3; --l) {
    std::vector<bool> met(count(l - 1), false);
    for (uint32_t k : seen[l]) {
      std::pair<uint32_t, uint32_t> kids[8];  // (Morton octant, child)
      uint32_t n = 0;
      children(l, k, [&](uint32_t octant, uint32_t child) { kids[n++] = {octant, child}; });
      std::sort(kids, kids + n);
      for (uint32_t j = 0; j < n; ++j)
        if (!met[kids[j].second]) {
          met[kids[j].second] = true;
          seen[l - 1].push_back(kids[j].second);
        }
    }
    for (uint32_t i = 0; i < met.size(); ++i)
      if (!met[i]) seen[l - 1].push_back(i);
  }
  return seen;
}

// The resident encoding's order: by descending reference count (pointers from the level above, each counted;
// the root once), so popular nodes get short offsets, ties by first_met_order.
template <class Count, class Children>
std::vector<std::vector<uint32_t>> resident_node_order(uint32_t L, Count&& count, Children&& children) {
  std::vector<std::vector<uint32_t>> order = first_met_order(L, count, children);
  for (uint32_t l = 2; l < L; ++l) {
    std::vector<uint32_t> refs(count(l), 0);
    for (uint32_t k = 0; k < count(l + 1); ++k) children(l + 1, k, [&](uint32_t, uint32_t child) { ++refs[child]; });
    std::stable_sort(order[l].begin(), order[l].end(), [&](uint32_t a, uint32_t b) { return refs[a] > refs[b]; });
  }
  return order;
}

}  // namespace mv
