#include "omicron_front.h"

#include <algorithm>

#include "megavox/error.h"

namespace mv::points {

void OmicronFront::update(const FineEnough& fine_enough) {
  insert_placeholders();
  settle();
  substitute();
  // Each pass moves a node at most one level; a front stable for the camera is reached within twice the depth.
  for (uint32_t pass = 0; pass < 2 * (b_.rule().depth + 2) && prune_and_branch(fine_enough); ++pass) {
  }
}

void OmicronFront::append_points(const FrontEntry& e, std::vector<uint64_t>& order) const {
  const LodNode& n = node(e);
  if (n.child_mask == 0)
    for (uint64_t q = n.first; q < n.first + n.points; ++q) order.push_back(q);
  else
    order.insert(order.end(), b_.reps().begin() + n.rep_begin, b_.reps().begin() + n.rep_begin + n.rep_count);
}

void OmicronFront::insert_placeholders() {
  const uint32_t deepest = b_.rule().depth;
  const std::vector<LodNode>& leaves = b_.level(deepest);
  for (; inserted_ < leaves.size(); ++inserted_) {
    front_.push_back({deepest, inserted_, true});
    ++stats_.placeholders;
  }
}

// Leaves whose parent was made since the last update and kept them (a collapsing parent absorbs its leaves); the
// root, a leaf of a finished tiny cloud, once the stream has ended.
void OmicronFront::settle() {
  const uint32_t deepest = b_.rule().depth;
  for (uint32_t l = 0; l <= deepest; ++l) {
    uint64_t end = b_.first_root(l);
    const bool finished = l == 0 && b_.frontier() == (uint64_t{1} << (3 * deepest)) && b_.level(0).size() == 1;
    if (finished) end = 1;
    for (; scan_[l] < end; ++scan_[l]) {
      const LodNode& n = b_.level(l)[scan_[l]];
      if (n.child_mask == 0 && !n.absorbed) settled_[l].push_back(scan_[l]);
    }
  }
}

void OmicronFront::substitute() {
  const uint32_t deepest = b_.rule().depth;
  std::vector<FrontEntry> out;
  out.reserve(front_.size());
  int64_t last_level = -1;  // the settled leaf put in last, while the placeholders it covers follow
  uint64_t last_prefix = 0;
  for (const FrontEntry& e : front_) {
    if (!e.placeholder) {
      out.push_back(e);
      last_level = -1;
      continue;
    }
    const uint64_t p = node(e).prefix;
    if (last_level >= 0 && (p >> (3 * (deepest - last_level))) == last_prefix) continue;  // covered already
    last_level = -1;
    // Per level, the first settled leaf is the only candidate: both lists run in Morton order (notes §7.2).
    for (uint32_t l = 0; l <= deepest && last_level < 0; ++l) {
      if (settled_[l].empty()) continue;
      const uint64_t i = settled_[l].front();
      const uint64_t leaf = b_.level(l)[i].prefix;
      if ((p >> (3 * (deepest - l))) != leaf) continue;
      out.push_back({l, i, false});
      settled_[l].pop_front();
      ++stats_.substituted;
      last_level = l;
      last_prefix = leaf;
    }
    if (last_level < 0) out.push_back(e);
  }
  front_.swap(out);
  for (uint32_t l = 0; l <= deepest; ++l)
    if (!settled_[l].empty())
      throw Error("points: internal error: a settled leaf at level " + std::to_string(l) + " has no placeholder in the front");
}

bool OmicronFront::prune_and_branch(const FineEnough& fine_enough) {
  bool changed = false;
  std::vector<FrontEntry> out;
  out.reserve(front_.size());
  for (size_t k = 0; k < front_.size();) {
    const FrontEntry e = front_[k];
    if (e.placeholder) {
      out.push_back(e);
      ++k;
      continue;
    }
    const LodNode& n = node(e);
    // Prune: e starts its parent's sibling group, the whole group follows in the front, the parent is made.
    if (e.level > 0 && e.at < b_.first_root(e.level)) {
      const std::vector<LodNode>& above = b_.level(e.level - 1);
      const auto it = std::lower_bound(above.begin(), above.end(), n.prefix >> 3,
                                       [](const LodNode& a, uint64_t prefix) { return a.prefix < prefix; });
      if (it != above.end() && it->prefix == (n.prefix >> 3) && it->child_begin == e.at && it->child_mask != 0) {
        const size_t group = static_cast<size_t>(__builtin_popcount(it->child_mask));
        bool whole = k + group <= front_.size();
        for (size_t j = 0; whole && j < group; ++j) {
          const FrontEntry& s = front_[k + j];
          whole = !s.placeholder && s.level == e.level && s.at == e.at + j;
        }
        if (whole && fine_enough(e.level - 1, it->prefix)) {
          out.push_back({e.level - 1, static_cast<uint64_t>(it - above.begin()), false});
          k += group;
          ++stats_.pruned;
          changed = true;
          continue;
        }
      }
    }
    // Branch: an inner node too coarse for the camera gives way to its children (made with it).
    if (n.child_mask != 0 && !fine_enough(e.level, n.prefix)) {
      const uint32_t children = static_cast<uint32_t>(__builtin_popcount(n.child_mask));
      for (uint32_t c = 0; c < children; ++c) out.push_back({e.level + 1, n.child_begin + c, false});
      ++stats_.branched;
      changed = true;
      ++k;
      continue;
    }
    out.push_back(e);
    ++k;
  }
  front_.swap(out);
  return changed;
}

}  // namespace mv::points
