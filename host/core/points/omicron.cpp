#include "omicron.h"

#include <algorithm>

#include "huge_pages.h"
#include "megavox/error.h"
#include "megavox/segmented.h"
#include "primitives/chunking.h"
#include "omicron_representatives.h"
#include "point_kernels.h"

namespace mv::points {

namespace {

// Candidates per selection call: their positions and codes take 16 bytes each on the host.
constexpr uint64_t kCallCandidates = uint64_t{1} << 24;
// Codes per leaf-cell segmentation, each with its device bytes: the code, its head flag, its run number and at
// most one run start.
constexpr uint64_t kLeafChunk = uint64_t{1} << 23;
constexpr uint64_t kLeafBytes = 8 + 4 + 4 + 4;

}  // namespace

OmicronBuilder::OmicronBuilder(Device& dev, const OmicronRule& rule)
    : dev_(dev), rule_(rule), levels_(rule.depth + 1), parented_(rule.depth + 1, 0) {
  if (rule.depth > 21) throw Error("points: depth " + std::to_string(rule.depth) + " is over 21, the deepest level 63-bit Morton codes hold");
  if (rule.max_node_points == 0) throw CodedError(ErrorCode::invalid_argument, "points: the node point limit must be at least 1", setting_max_node_points);
  if (rule.top_level > rule.depth) throw Error("points: internal error: the top level is below the leaves");
}

OmicronPart OmicronBuilder::take_part() {
  OmicronPart part;
  part.top_level = rule_.top_level;
  part.points = formed_;
  for (uint32_t l = rule_.top_level; l <= rule_.depth; ++l) part.levels.push_back(std::move(levels_[l]));
  part.reps = std::move(reps_);
  return part;
}

void OmicronBuilder::join(OmicronPart&& part, uint64_t first_point) {
  if (part.levels.size() != rule_.depth + 1 - part.top_level || part.top_level == 0 ||
      (joined_top_ != 0 && joined_top_ != part.top_level) || first_point != formed_)
    throw Error("points: internal error: a rank's part does not fit the join");
  joined_top_ = part.top_level;
  const uint64_t rep_offset = reps_.size();
  // A node's children are the next nodes of the level below: count from where this part's start there.
  std::vector<uint64_t> below(part.levels.size() + 1, 0);
  for (uint32_t l = part.top_level; l <= rule_.depth; ++l) below[l - part.top_level] = l < rule_.depth ? levels_[l + 1].size() : 0;
  for (uint32_t l = part.top_level; l <= rule_.depth; ++l) {
    for (LodNode n : part.levels[l - part.top_level]) {
      n.first += first_point;
      if (n.child_mask != 0) {
        n.rep_begin += rep_offset;
        n.child_begin += below[l - part.top_level];
      }
      levels_[l].push_back(n);
    }
  }
  reps_.reserve(rep_offset + part.reps.size());
  for (uint64_t q : part.reps) reps_.push_back(q + first_point);
  formed_ += part.points;
}

void OmicronBuilder::finish_join(std::span<const uint64_t> sorted) {
  if (sorted.size() != formed_) throw Error("points: internal error: the join's codes are not its parts' points");
  for (uint32_t l = joined_top_ + 1; l <= rule_.depth; ++l) parented_[l] = levels_[l].size();
  frontier_ = uint64_t{1} << (3 * rule_.depth);
  fix(sorted);
}

uint64_t OmicronBuilder::concatenate(std::span<const uint64_t> sorted, bool last) {
  const uint32_t leaf_shift = 3 * (21 - rule_.depth);
  const uint64_t n = sorted.size();
  std::vector<LodNode>& leaves = levels_[rule_.depth];
  // The leaf cells' boundaries over the new codes are found on the device (a segmentation by leaf cell, chunk by
  // chunk); the host walks the cells. A cell runs on until the next one starts: the last cell seen stays open
  // unless this is the last prefix, as it may go on in the next.
  bool open = false;
  LodNode leaf;
  const uint64_t chunk =
      formed_ < n ? std::min(kLeafChunk, detail::device_chunk(dev_, "leaf cells", kLeafBytes, 8)) : 1;
  std::vector<uint32_t> starts;
  for (uint64_t at = formed_; at < n; at += chunk) {
    const uint64_t m = std::min(chunk, n - at);
    Buffer codes = dev_.alloc(m * 8, "leaf codes");
    dev_.upload(codes, sorted.data() + at, m * 8);
    dev_.barrier();
    const Segmentation cells = segment_by_key(dev_, codes, m, leaf_shift);
    starts.resize(cells.count + 1);
    dev_.download(cells.starts, starts.data(), starts.size() * 4);
    for (uint64_t s = 0; s < cells.count; ++s) {
      const uint64_t first = at + starts[s];
      const uint64_t cell = sorted[first] >> leaf_shift;
      if (open && leaf.prefix == cell) continue;  // a cell across the chunks' seam
      if (open) {
        leaf.points = first - leaf.first;
        leaves.push_back(leaf);
      }
      if (!leaves.empty() && leaves.back().prefix >= cell)
        throw Error("points: the sorted stream is out of order at point " + std::to_string(first));
      leaf = LodNode{};
      leaf.prefix = cell;
      leaf.first = first;
      open = true;
    }
  }
  uint64_t i = open ? leaf.first : formed_;
  if (open && last) {
    leaf.points = n - leaf.first;
    leaves.push_back(leaf);
    i = n;
  }
  formed_ = i;
  if (last) frontier_ = uint64_t{1} << (3 * rule_.depth);
  else if (i < n) frontier_ = sorted[i] >> leaf_shift;
  fix(sorted);
  return frontier_;
}

void OmicronBuilder::fix(std::span<const uint64_t> sorted) {
  ++stats_.fixes;
  for (uint32_t l = rule_.depth; l > rule_.top_level; --l) {
    std::vector<LodNode>& list = levels_[l];
    const uint32_t to_leaf = 3 * (rule_.depth - (l - 1));  // a parent's code times 8^to_leaf is its first leaf cell
    // Complete groups of sibling roots, in Morton order: a parent is complete when its span is before the frontier.
    std::vector<std::pair<uint64_t, uint64_t>> groups;
    uint64_t r = parented_[l];
    while (r < list.size()) {
      const uint64_t parent = list[r].prefix >> 3;
      if (((parent + 1) << to_leaf) > frontier_) break;
      uint64_t s = r + 1;
      while (s < list.size() && (list[s].prefix >> 3) == parent) ++s;
      groups.emplace_back(r, s);
      r = s;
    }
    if (groups.empty()) continue;

    std::vector<LodNode> parents(groups.size());
    std::vector<size_t> inner;  // parents that keep representatives
    for (size_t g = 0; g < groups.size(); ++g) {
      LodNode& p = parents[g];
      p.child_begin = groups[g].first;
      p.prefix = list[groups[g].first].prefix >> 3;
      p.first = list[groups[g].first].first;
      bool all_leaves = true;
      for (uint64_t c = groups[g].first; c < groups[g].second; ++c) {
        p.points += list[c].points;
        p.child_mask |= static_cast<uint8_t>(1u << (list[c].prefix & 7));
        all_leaves &= list[c].child_mask == 0;
      }
      if (all_leaves && p.points <= rule_.max_node_points) {
        p.child_mask = 0;  // leaf collapse: the parent holds its children's points
        for (uint64_t c = groups[g].first; c < groups[g].second; ++c) list[c].absorbed = true;
      } else {
        inner.push_back(g);
      }
    }

    // Representatives of the inner parents, in calls of at most kCallCandidates candidates (a parent's own
    // candidates may exceed that: it then has a call to itself).
    const uint32_t fine = (l - 1) + rule_.grid_bits;
    const uint32_t cell_bits = fine >= 21 ? 0 : 3 * (21 - fine);
    // A parent whose children are all leaves (every parent of the deepest level's cells) has one contiguous range
    // of the sorted stream as its candidates: its codes are copied as a block, and a kept position maps back by
    // offset. Other parents list their candidates one by one (cand_).
    size_t k = 0;
    while (k < inner.size()) {
      std::vector<uint64_t>& cand = cand_;  // reused across calls: fresh memory is slow to touch
      std::vector<uint64_t>& codes = cand_codes_;
      cand.clear();
      codes.clear();
      std::vector<uint32_t> bounds{0};
      std::vector<int64_t> range_first;  // per parent of the call: its first sorted point if its candidates are a range
      size_t end = k;
      while (end < inner.size()) {
        const auto [b, e] = groups[inner[end]];
        uint64_t size = 0;
        bool all_leaves = true;
        for (uint64_t c = b; c < e; ++c) {
          size += list[c].child_mask == 0 ? list[c].points : list[c].rep_count;
          all_leaves &= list[c].child_mask == 0;
        }
        if (end > k && codes.size() + size > kCallCandidates) break;
        if (codes.size() + size > UINT32_MAX) throw Error("points: a node has more than 2^32 candidate points");
        if (all_leaves) {
          const uint64_t first = list[b].first;
          if (list[e - 1].first + list[e - 1].points != first + size)
            throw Error("points: internal error: sibling leaves do not cover one range of the sorted stream");
          codes.insert(codes.end(), sorted.begin() + first, sorted.begin() + first + size);
          range_first.push_back(static_cast<int64_t>(first));
        } else {
          range_first.push_back(-1);
          const size_t from = cand.size();
          for (uint64_t c = b; c < e; ++c) {
            const LodNode& child = list[c];
            if (child.child_mask == 0)
              for (uint64_t q = child.first; q < child.first + child.points; ++q) cand.push_back(q);
            else
              cand.insert(cand.end(), reps_.begin() + child.rep_begin, reps_.begin() + child.rep_begin + child.rep_count);
          }
          for (size_t q = from; q < cand.size(); ++q) codes.push_back(sorted[cand[q]]);
        }
        bounds.push_back(static_cast<uint32_t>(codes.size()));
        ++end;
      }
      RepSelection sel = select_representatives(dev_, codes, bounds, cell_bits, rule_.max_node_points);
      ++stats_.dispatches;
      // reps_ grows geometrically on huge pages (tens of millions of entries at 100M points)
      const uint64_t at = reps_.size();
      if (at + sel.positions.size() > reps_.capacity())
        reserve_huge(reps_, std::max<uint64_t>(at + sel.positions.size(), 2 * reps_.capacity()));
      reps_.resize(at + sel.positions.size());
      uint64_t listed = 0;  // candidates of the listed parents before this one
      for (size_t g = k; g < end; ++g) {
        LodNode& p = parents[inner[g]];
        const uint64_t b = bounds[g - k];
        p.rep_begin = at + sel.offsets[g - k];
        p.rep_count = static_cast<uint32_t>(sel.offsets[g - k + 1] - sel.offsets[g - k]);
        const int64_t first = range_first[g - k];
        uint64_t* out = reps_.data() + p.rep_begin;
        const uint32_t* pos = sel.positions.data() + sel.offsets[g - k];  // within the call's candidates
        if (first >= 0) {
          for (uint32_t q = 0; q < p.rep_count; ++q) out[q] = static_cast<uint64_t>(first) + (pos[q] - b);
        } else {
          for (uint32_t q = 0; q < p.rep_count; ++q) out[q] = cand[listed + (pos[q] - b)];
          listed += bounds[g - k + 1] - b;
        }
      }
      k = end;
    }
    parented_[l] = r;
    levels_[l - 1].insert(levels_[l - 1].end(), parents.begin(), parents.end());
  }
}

PointNode output_node(const LodNode& src, uint32_t level, uint64_t first_point, NodePoints& points) {
  PointNode node;
  node.code = (uint64_t{1} << (3 * level)) | src.prefix;
  node.level = static_cast<uint8_t>(level);
  node.subtree_points = src.points;
  node.first_point = first_point;
  node.child_mask = src.child_mask;
  if (src.child_mask == 0) points = {src.first, static_cast<uint32_t>(src.points), false};
  else points = {src.rep_begin, src.rep_count, true};
  node.point_count = points.count;
  return node;
}

PointNode OmicronBuilder::emit(const LodNode& src, uint32_t level, std::vector<uint64_t>& order) const {
  NodePoints points;
  PointNode node = output_node(src, level, order.size(), points);
  const NodePoints one[1] = {points};
  expand_order(one, reps_, order);
  return node;
}

void part_nodes(const OmicronPart& part, const std::vector<bool>& top_absorbed, std::vector<PointNode>& nodes,
                std::vector<NodePoints>& sources) {
  uint64_t first_point = 0;
  for (size_t k = 0; k < part.levels.size(); ++k) {
    const uint32_t level = part.top_level + static_cast<uint32_t>(k);
    for (size_t i = 0; i < part.levels[k].size(); ++i) {
      const LodNode& src = part.levels[k][i];
      if (src.absorbed || (k == 0 && top_absorbed.at(i))) continue;
      NodePoints points;
      nodes.push_back(output_node(src, level, first_point, points));
      sources.push_back(points);
      first_point += points.count;
    }
  }
}

void expand_order(std::span<const NodePoints> sources, std::span<const uint64_t> reps, std::vector<uint64_t>& order) {
  for (const NodePoints& s : sources) {
    if (s.reps) {
      order.insert(order.end(), reps.begin() + static_cast<std::ptrdiff_t>(s.first),
                   reps.begin() + static_cast<std::ptrdiff_t>(s.first + s.count));
    } else {
      for (uint64_t q = s.first; q < s.first + s.count; ++q) order.push_back(q);
    }
  }
}

void OmicronBuilder::snapshot(std::vector<PointNode>& nodes, std::vector<uint64_t>& order,
                              std::vector<uint32_t>& roots) const {
  nodes.clear();
  order.clear();
  reserve_huge(order, formed_ + reps_.size());  // every leaf point and representative at most once
  roots.clear();
  struct Item {
    uint32_t level;
    uint64_t at;
  };
  for (uint32_t l = 0; l <= rule_.depth; ++l)
    for (uint64_t r = parented_[l]; r < levels_[l].size(); ++r) {
      roots.push_back(static_cast<uint32_t>(nodes.size()));
      std::vector<Item> queue{{l, r}};
      for (size_t q = 0; q < queue.size(); ++q) {
        const LodNode& src = levels_[queue[q].level][queue[q].at];
        PointNode node = emit(src, queue[q].level, order);
        if (src.child_mask != 0) {
          node.first_child = static_cast<uint32_t>(nodes.size() + queue.size() - q);
          const uint32_t children = static_cast<uint32_t>(__builtin_popcount(src.child_mask));
          for (uint32_t c = 0; c < children; ++c) queue.push_back({queue[q].level + 1, src.child_begin + c});
        }
        nodes.push_back(node);
      }
    }
}

void OmicronBuilder::assemble(std::vector<PointNode>& nodes, std::vector<NodePoints>& sources,
                              std::vector<uint64_t>& per_level) const {
  if (levels_[0].size() != 1)
    throw Error("points: the hierarchy is not finished (" + std::to_string(levels_[0].size()) + " roots)");
  nodes.clear();
  sources.clear();
  per_level.assign(rule_.depth + 1, 0);
  // Breadth-first: level by level, each level's nodes in Morton order, so a node's children are the next
  // survivors of the level below.
  std::vector<uint64_t> survivors(rule_.depth + 2, 0);
  for (uint32_t l = 0; l <= rule_.depth; ++l)
    for (const LodNode& src : levels_[l]) survivors[l] += src.absorbed ? 0 : 1;
  uint64_t next_level_start = 0;  // index of the first node of the level below
  uint64_t first_point = 0;
  for (uint32_t l = 0; l <= rule_.depth; ++l) {
    next_level_start += survivors[l];
    uint64_t children_taken = 0;
    for (const LodNode& src : levels_[l]) {
      if (src.absorbed) continue;
      NodePoints points;
      PointNode node = output_node(src, l, first_point, points);
      first_point += points.count;
      if (src.child_mask != 0) {
        node.first_child = static_cast<uint32_t>(next_level_start + children_taken);
        children_taken += static_cast<uint64_t>(__builtin_popcount(src.child_mask));
      }
      nodes.push_back(node);
      sources.push_back(points);
      ++per_level[l];
    }
  }
  while (per_level.size() > 1 && per_level.back() == 0) per_level.pop_back();
}

}  // namespace mv::points
