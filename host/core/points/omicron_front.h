// OMiCroN's rendering front (da Silva et al., "OMiCroN", Sec. 6) over a growing
// OmicronBuilder: the nodes a frame draws, kept across frames and changed in place as the lists grow, instead
// of a fresh cut of the whole forest per frame.
//
// - Every deepest-level leaf enters the front as a placeholder when concatenate forms it (insertPlaceholder:
//   appended at the end, which keeps the front in Morton order of spans, invariant 2.1).
// - A leaf is settled once its parent exists and did not absorb it (leaf collapse can still merge a leaf without
//   a parent into one). Settled leaves wait in per-level lists in Morton order; one pass over the front puts each
//   in place of the run of placeholders it covers (ancestor-or-self; a collapsed leaf covers several). After an
//   update no placeholder is left whose settled leaf exists.
// - Stable nodes (never placeholders) branch into their children when too coarse for the camera and prune into
//   their parent when the parent is fine enough, the whole sibling group adjacent in the front and the parent
//   made already (invariant 2.2: nodes without a parent never enter through prune, and placeholders never prune).
//   Passes repeat until nothing changes, so a frame's front is the cut for its camera.
#pragma once
#include <cstdint>
#include <deque>
#include <functional>
#include <vector>

#include "omicron.h"

namespace mv::points {

struct FrontEntry {
  uint32_t level = 0;
  uint64_t at = 0;           // index into the builder's list of that level
  bool placeholder = false;  // a deepest-level leaf not settled yet
};

struct FrontStats {
  uint64_t placeholders = 0;  // inserted, in all
  uint64_t substituted = 0;   // settled leaves put in place of their placeholders
  uint64_t branched = 0, pruned = 0;
};

class OmicronFront {
 public:
  // fine_enough(level, prefix): a node's points are dense enough on screen to be drawn instead of its children.
  using FineEnough = std::function<bool(uint32_t level, uint64_t prefix)>;
  explicit OmicronFront(const OmicronBuilder& builder) : b_(builder), scan_(builder.rule().depth + 1, 0),
                                                         settled_(builder.rule().depth + 1) {}

  // One evaluation after the builder's latest concatenate: placeholders for the new leaves, substitution, then
  // prune and branch until the front is stable for `fine_enough`.
  void update(const FineEnough& fine_enough);

  const std::vector<FrontEntry>& entries() const { return front_; }
  const FrontStats& stats() const { return stats_; }
  // An entry's points, as sorted positions: a leaf's (or placeholder's) run, an inner node's representatives.
  void append_points(const FrontEntry& e, std::vector<uint64_t>& order) const;

 private:
  const LodNode& node(const FrontEntry& e) const { return b_.level(e.level)[e.at]; }
  void insert_placeholders();
  void settle();
  void substitute();
  bool prune_and_branch(const FineEnough& fine_enough);

  const OmicronBuilder& b_;
  std::vector<FrontEntry> front_;
  uint64_t inserted_ = 0;                       // deepest-level leaves given a placeholder
  std::vector<uint64_t> scan_;                  // per level: nodes before this were checked for settling
  std::vector<std::deque<uint64_t>> settled_;   // per level: settled leaves awaiting substitution
  FrontStats stats_;
};

}  // namespace mv::points
