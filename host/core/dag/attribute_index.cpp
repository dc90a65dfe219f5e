// Depth-first attribute indices recovered from subtree sizes (megavox/colour.h). With a node's index i and its
// shown children c_0 < c_1 < ... (octants as the traversal sees them), child c_j's index is
// i + 1 + size(c_0) + ... + size(c_{j-1}): the offsets depend on sizes alone, so merged subtrees share them.
#include <bit>

#include "megavox/colour.h"

namespace mv {

std::vector<std::vector<uint64_t>> subtree_sizes(const Dag& dag) {
  std::vector<std::vector<uint64_t>> sizes(dag.levels + 1);
  for (uint32_t l = 1; l <= dag.levels; ++l) {
    const DagLevel& lv = dag.level[l];
    sizes[l].resize(lv.mask.size());
    for (size_t i = 0; i < lv.mask.size(); ++i) {
      uint64_t s = 1;
      if (l == 1) {
        s += std::popcount(lv.mask[i]);
      } else {
        const uint32_t k = std::popcount(lv.mask[i]);
        for (uint32_t j = 0; j < k; ++j) s += sizes[l - 1][lv.children[lv.first[i] + j]];
      }
      sizes[l][i] = s;
    }
  }
  return sizes;
}

namespace {

struct AttributeWalk {
  const Dag& dag;
  const std::vector<std::vector<uint64_t>>& sizes;
  const std::function<void(uint64_t, uint32_t, uint64_t)>& visit;

  // Node `id` of level l, shown mirrored by `flip` (octant c of the stored node appears at c ^ flip).
  void walk(uint32_t l, uint32_t id, uint32_t flip, uint64_t index, uint64_t code) const {
    visit(index, l, code);
    const DagLevel& lv = dag.level[l];
    const uint32_t mask = lv.mask[id];
    // The stored children by stored octant: their id, tag, subtree size.
    uint32_t child[8] = {}, tag[8] = {};
    uint64_t size[8] = {};
    for (uint32_t c = 0, j = 0; c < 8; ++c) {
      if (!(mask >> c & 1)) continue;
      if (l == 1) {
        size[c] = 1;
      } else {
        const uint32_t at = lv.first[id] + j++;
        child[c] = lv.children[at];
        tag[c] = lv.tags.empty() ? 0 : lv.tags[at];
        size[c] = sizes[l - 1][child[c]];
      }
    }
    uint64_t next = index + 1;
    for (uint32_t shown = 0; shown < 8; ++shown) {
      const uint32_t c = shown ^ flip;
      if (!(mask >> c & 1)) continue;
      const uint64_t child_code = code << 3 | shown;
      if (l == 1) visit(next, 0, child_code);
      else walk(l - 1, child[c], flip ^ tag[c], next, child_code);
      next += size[c];
    }
  }
};

}  // namespace

void for_each_attribute_index(const Dag& dag, const std::function<void(uint64_t, uint32_t, uint64_t)>& visit) {
  if (dag.levels == 0 || dag.voxels == 0) return;
  const auto sizes = subtree_sizes(dag);
  AttributeWalk{dag, sizes, visit}.walk(dag.levels, 0, 0, 0, 0);
}

}  // namespace mv
