// The OMiCroN construction (da Silva et al., docs/ARCHITECTURE.md "Point clouds"): a point hierarchy built
// bottom-up from a Morton-sorted stream while the stream is still arriving.
//
// The oblique cut: every leaf cell (level `depth`) before `frontier` has all of its points; a node whose
// deepest descendant cell lies before the frontier (span < frontier) is complete. Per-level lists hold the
// subtree roots that have no parent yet. concatenate() appends the leaves of a longer sorted prefix to the
// deepest list; fix() then walks the lists bottom-up and gives every complete group of sibling roots its
// parent, all of a level's parents in one kernel dispatch pair (point_kernels.h): afterwards each list holds at
// most 7 roots, the complete children of the one node the frontier cuts. A parent whose children are all leaves
// and whose subtree holds at most max_node_points points becomes a leaf itself (OMiCroN's leaf collapse, which
// leaves leaves above the deepest level); otherwise it keeps one representative per cell of its sub-grid,
// copies of its children's points. finish() fixes with the frontier past the end, which leaves the root.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "megavox/device.h"
#include "megavox/points.h"

namespace mv::points {

struct OmicronRule {
  uint32_t depth = 0;            // the leaf level, at most 21
  uint32_t max_node_points = 0;  // leaf collapse threshold and the cap on representatives
  uint32_t grid_bits = 6;        // an inner node at level l keeps one point per cell of level l + grid_bits
  // Parents are made down to this level only: the nodes of level top_level stay roots. A build over ranks
  // (point_ranks.cpp) gives each rank whole subtrees of that level, and joins the levels above on rank 0.
  uint32_t top_level = 0;
};


// A node of the lists: its subtree is the sorted points [first, first + points).
struct LodNode {
  uint64_t prefix = 0;     // Morton prefix at its level (no sentinel bit)
  uint64_t first = 0;
  uint64_t points = 0;
  uint64_t rep_begin = 0;  // an inner node's representatives: reps()[rep_begin, rep_begin + rep_count)
  uint32_t rep_count = 0;
  uint64_t child_begin = 0;  // an inner node's children: the next popcount(child_mask) nodes of the level below
  uint8_t child_mask = 0;  // 0: a leaf
  bool absorbed = false;   // a leaf merged into its parent by leaf collapse
};

// Where an output node's points come from: the sorted points [first, first + count) for a leaf, the
// representatives reps()[first, first + count) for an inner node.
struct NodePoints {
  uint64_t first = 0;
  uint32_t count = 0;
  bool reps = false;
};

// A builder's lists from its top level down, after concatenate(..., true) with rule.top_level > 0: what one
// rank of a build over ranks sends for the join. Positions (first, reps) count from the rank's first point.
struct OmicronPart {
  uint32_t top_level = 0;
  std::vector<std::vector<LodNode>> levels;  // index = level - top_level
  std::vector<uint64_t> reps;
  uint64_t points = 0;
};

// A node of the output (all but first_child) whose points start at first_point of node order, and where they
// come from.
PointNode output_node(const LodNode& src, uint32_t level, uint64_t first_point, NodePoints& points);

// The nodes of a rank's part that the hierarchy keeps, level by level, each level in Morton order, and where
// their points come from (positions in the part's): those it did not absorb, and of its top level those the
// join did not (top_absorbed[k] for its k-th). first_child is not set.
void part_nodes(const OmicronPart& part, const std::vector<bool>& top_absorbed, std::vector<PointNode>& nodes,
                std::vector<NodePoints>& sources);

// The flat node order those sources describe: point i of node order is sorted point order[i].
void expand_order(std::span<const NodePoints> sources, std::span<const uint64_t> reps, std::vector<uint64_t>& order);

struct OmicronStats {
  uint64_t fixes = 0;
  uint64_t dispatches = 0;    // representative selections (each a few dispatches over one call's candidates)
};

class OmicronBuilder {
 public:
  OmicronBuilder(Device& dev, const OmicronRule& rule);

  // `sorted` is the whole sorted prefix so far (each call's span starts where the last one's did, and is at
  // least as long). Forms the leaves of every cell before the last one seen (all of them with `last`), then
  // fixes. Returns the frontier: leaf cells below it are complete.
  uint64_t concatenate(std::span<const uint64_t> sorted, bool last);

  // The lists of rule().top_level and below (a build over ranks), after concatenate(..., true).
  OmicronPart take_part();
  // Appends a rank's part whose first point is sorted point `first_point` of the whole cloud (parts in Morton
  // order, each over whole subtrees of its top level); after the last, finish_join makes the levels above with
  // `sorted`, every code of the cloud, as one builder over the whole stream would have.
  void join(OmicronPart&& part, uint64_t first_point);
  void finish_join(std::span<const uint64_t> sorted);

  // The hierarchy's nodes in breadth-first order, after concatenate(..., true), and where each node's points
  // come from (sources[i] for nodes[i]; with reps()); the caller gathers the columns.
  void assemble(std::vector<PointNode>& nodes, std::vector<NodePoints>& sources, std::vector<uint64_t>& per_level) const;

  // The finished part so far, as a forest: every subtree whose root has no parent yet (the lists' roots, every
  // level), breadth-first per root with children contiguous; roots[k] is root k's index in nodes. Point i of
  // node order is sorted point order[i].
  void snapshot(std::vector<PointNode>& nodes, std::vector<uint64_t>& order, std::vector<uint32_t>& roots) const;

  // The lists' state, for checkpoints: level l's nodes so far, the first of which without a parent yet.
  const std::vector<LodNode>& level(uint32_t l) const { return levels_[l]; }
  uint64_t first_root(uint32_t l) const { return parented_[l]; }
  const std::vector<uint64_t>& reps() const { return reps_; }
  std::vector<uint64_t> take_reps() { return std::move(reps_); }  // after assemble(), for the gather
  uint64_t formed() const { return formed_; }
  uint64_t frontier() const { return frontier_; }
  const OmicronRule& rule() const { return rule_; }
  const OmicronStats& stats() const { return stats_; }

 private:
  void fix(std::span<const uint64_t> sorted);
  // The same, its points appended to `order`.
  PointNode emit(const LodNode& src, uint32_t level, std::vector<uint64_t>& order) const;

  Device& dev_;
  OmicronRule rule_;
  std::vector<std::vector<LodNode>> levels_;  // index = level; each in Morton order
  std::vector<uint64_t> parented_;            // per level: nodes before this have a parent
  std::vector<uint64_t> reps_;                // sorted point positions of every inner node's representatives
  std::vector<uint64_t> cand_, cand_codes_;   // a selection call's candidates and their codes, reused
  uint64_t formed_ = 0;                       // sorted points already in a leaf
  uint64_t frontier_ = 0;
  uint32_t joined_top_ = 0;  // the parts' top level, once join() took one
  OmicronStats stats_;
};

}  // namespace mv::points
