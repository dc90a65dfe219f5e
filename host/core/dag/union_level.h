// One level of the union of the out-of-core cubes' partial DAGs (dag_by_cubes.cpp): nodes in their stored
// orientation, and one slot per child pointer (the union node it points to, the pointer's tag). Internal to
// host/dag.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mv::detail {

class UnionLevel {
 public:
  // dedupe: a node equal to one already held (same mask, same slots) is not added again. The reduction that
  // follows finds the same classes, ids and orientations either way (they depend on the distinct keys, not on
  // how often each occurs), so this only saves memory: neighbouring cubes share most of their lower nodes.
  explicit UnionLevel(bool dedupe = false) : dedupe_(dedupe) {}
  // A node: its mask and, above level 1 (nodes != nullptr), its children's union nodes and pointer tags, one
  // per set bit of the mask. Returns its index in the union.
  uint32_t add(uint32_t node_mask, const uint32_t* nodes, const uint32_t* tags);
  size_t size() const { return mask.size(); }

  std::vector<uint32_t> mask, first, slot_node, slot_tag;  // first and slots only above level 1

 private:
  uint64_t hash_of(uint32_t node_mask, const uint32_t* nodes, const uint32_t* tags) const;
  bool equals(uint32_t index, uint32_t node_mask, const uint32_t* nodes, const uint32_t* tags) const;
  void grow();
  bool dedupe_;
  std::vector<uint32_t> table_;  // open addressing, node index + 1 (0 = empty)
};

}  // namespace mv::detail
