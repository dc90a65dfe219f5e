// The union of the cubes' partial DAGs, one level, with optional exact deduplication (union_level.h).
#include "union_level.h"

#include <bit>

#include "megavox/error.h"

namespace mv::detail {

namespace {
uint64_t mix(uint64_t h, uint64_t x) {
  h ^= x + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
  h *= 0xbf58476d1ce4e5b9ull;
  return h ^ (h >> 31);
}
}  // namespace

uint64_t UnionLevel::hash_of(uint32_t node_mask, const uint32_t* nodes, const uint32_t* tags) const {
  uint64_t h = mix(0, node_mask);
  if (nodes)
    for (int k = 0; k < std::popcount(node_mask); ++k) h = mix(h, uint64_t{nodes[k]} << 3 | tags[k]);
  return h;
}

bool UnionLevel::equals(uint32_t index, uint32_t node_mask, const uint32_t* nodes, const uint32_t* tags) const {
  if (mask[index] != node_mask) return false;
  if (!nodes) return true;
  const uint32_t at = first[index];
  for (int k = 0; k < std::popcount(node_mask); ++k)
    if (slot_node[at + k] != nodes[k] || slot_tag[at + k] != tags[k]) return false;
  return true;
}

void UnionLevel::grow() {
  table_.assign(table_.empty() ? 1024 : 2 * table_.size(), 0);
  const size_t wrap = table_.size() - 1;
  for (uint32_t i = 0; i < mask.size(); ++i) {
    const uint32_t* nodes = first.empty() ? nullptr : &slot_node[first[i]];
    const uint32_t* tags = first.empty() ? nullptr : &slot_tag[first[i]];
    size_t s = hash_of(mask[i], nodes, tags) & wrap;
    while (table_[s]) s = (s + 1) & wrap;
    table_[s] = i + 1;
  }
}

uint32_t UnionLevel::add(uint32_t node_mask, const uint32_t* nodes, const uint32_t* tags) {
  if (mask.size() >= UINT32_MAX - 1) throw Error("out-of-core build: more than 2^32 nodes in one merged level");
  size_t slot = 0;
  if (dedupe_) {
    if (2 * (mask.size() + 1) > table_.size()) grow();
    const size_t wrap = table_.size() - 1;
    for (slot = hash_of(node_mask, nodes, tags) & wrap; table_[slot]; slot = (slot + 1) & wrap)
      if (equals(table_[slot] - 1, node_mask, nodes, tags)) return table_[slot] - 1;
  }
  const auto index = static_cast<uint32_t>(mask.size());
  mask.push_back(node_mask);
  if (nodes) {
    first.push_back(static_cast<uint32_t>(slot_node.size()));
    slot_node.insert(slot_node.end(), nodes, nodes + std::popcount(node_mask));
    slot_tag.insert(slot_tag.end(), tags, tags + std::popcount(node_mask));
  }
  if (dedupe_) table_[slot] = index + 1;
  return index;
}

}  // namespace mv::detail
