#include "point_ranks_mvx.h"

#include <algorithm>
#include <string>

#include "megavox/error.h"
#include "megavox/rank_message.h"
#include "point_gather.h"

namespace mv::points {

namespace {

constexpr uint64_t kPiece = uint64_t{64} << 20;  // bytes a rank hands rank 0 at a time

// Collective: each other rank's `bytes` at `data` to rank 0, in rank order and in pieces, where `put` takes them.
// Returns the bytes this rank sent or received.
uint64_t pass_to_lead(const RankCollectives& ranks, const uint8_t* data, uint64_t bytes, const PutPointBytes* put) {
  MessageWriter w;
  w.put(bytes);
  std::vector<uint64_t> sizes;
  for (const std::vector<uint8_t>& b : ranks.all_gather(w.bytes)) sizes.push_back(MessageReader(b).get<uint64_t>());
  uint64_t moved = 0;
  for (int r = 1; r < ranks.size; ++r) {
    const uint64_t size = sizes[static_cast<size_t>(r)];
    for (uint64_t at = 0; at < size; at += kPiece) {
      const uint64_t n = std::min(kPiece, size - at);
      std::vector<uint8_t> piece;
      if (ranks.rank == r) piece.assign(data + at, data + at + n), moved += n;
      const RankBytes got = ranks.gather(std::move(piece));
      if (ranks.rank != 0) continue;
      if (got.at(static_cast<size_t>(r)).size() != n) throw Error("points: internal error: a rank's points came short");
      (*put)(got[static_cast<size_t>(r)].data(), n);
      moved += n;
    }
  }
  return moved;
}

// The columns write_mvx_points writes, in its order, and their bytes a point.
struct Column {
  PointColumn kind;
  uint64_t per_point;
};
std::vector<Column> columns_of(const PointCloudInfo& info) {
  std::vector<Column> c{{PointColumn::xyz, 12}};
  if (info.attributes & kPointRgb) c.push_back({PointColumn::rgb, 6});
  if (info.attributes & kPointNormal) c.push_back({PointColumn::normal, 12});
  if (info.attributes & kPointIntensity) c.push_back({PointColumn::intensity, 2});
  if (info.attributes & kPointExtra) c.push_back({PointColumn::extra, info.extra_bytes});
  return c;
}

const uint8_t* column_data(const PointColumns& p, PointColumn c) {
  switch (c) {
    case PointColumn::xyz: return reinterpret_cast<const uint8_t*>(p.xyz.data());
    case PointColumn::rgb: return reinterpret_cast<const uint8_t*>(p.rgb.data());
    case PointColumn::normal: return reinterpret_cast<const uint8_t*>(p.normal.data());
    case PointColumn::intensity: return reinterpret_cast<const uint8_t*>(p.intensity.data());
    case PointColumn::extra: return p.extra.data();
  }
  return nullptr;
}

}  // namespace

std::vector<bool> nodes_elsewhere(const PointHierarchy& h, const std::vector<int>& owner, uint32_t top_level) {
  std::vector<bool> elsewhere(h.nodes.size(), false);
  for (size_t i = 0; i < h.nodes.size(); ++i) {
    const PointNode& n = h.nodes[i];
    if (n.level < top_level) continue;
    const uint64_t cell = (n.code ^ (uint64_t{1} << (3 * n.level))) >> (3 * (n.level - top_level));
    elsewhere[i] = owner.at(cell) != 0;
  }
  return elsewhere;
}

void send_start(const RankCollectives& ranks, const StartMessage& common, const std::vector<std::vector<bool>>& absorbed) {
  if (ranks.sleepy_barrier) ranks.sleepy_barrier();  // the others wait there
  RankBytes parts(static_cast<size_t>(ranks.size));
  for (int r = 1; r < ranks.size; ++r) {
    MessageWriter m;
    m.put_text(common.tmp);
    m.put(static_cast<uint8_t>(common.colour_shift));
    m.put(common.depth);
    std::vector<uint8_t> flags;
    for (bool a : absorbed.at(static_cast<size_t>(r))) flags.push_back(a ? 1 : 0);
    m.put_all(flags);
    parts[static_cast<size_t>(r)] = std::move(m.bytes);
  }
  ranks.all_to_all(std::move(parts));
}

StartMessage receive_start(const RankCollectives& ranks, size_t top_nodes) {
  if (ranks.sleepy_barrier) ranks.sleepy_barrier();  // asleep while rank 0 joins the parts
  const RankBytes got = ranks.all_to_all(RankBytes(static_cast<size_t>(ranks.size)));
  MessageReader in(got.at(0));
  StartMessage s;
  s.tmp = in.text();
  s.colour_shift = in.get<uint8_t>();
  s.depth = in.get<uint32_t>();
  std::vector<uint8_t> flags;
  in.get_all(flags);
  if (flags.size() != top_nodes) throw Error("points: internal error: rank 0's start message does not fit");
  s.absorbed.assign(flags.begin(), flags.end());
  return s;
}

PointsElsewhere lead_points_share(const RankCollectives& ranks, const PointHierarchy& h, const std::vector<int>& owner,
                                  uint32_t top_level, std::vector<std::vector<bool>> absorbed, uint64_t& exchanged) {
  PointsElsewhere share;
  share.elsewhere = nodes_elsewhere(h, owner, top_level);
  StartMessage common;
  common.depth = static_cast<uint32_t>(h.nodes_per_level.size() - 1);  // h.depth is set after the share
  // Now: the others put their points in node order while this rank gathers its own.
  send_start(ranks, common, absorbed);
  share.others = [&ranks, top_level, &exchanged](PointColumn, uint32_t level, const PutPointBytes& put) {
    if (level >= top_level) exchanged += pass_to_lead(ranks, nullptr, 0, &put);
  };
  return share;
}

uint64_t send_part_points(const RankCollectives& ranks, const OmicronPart& part, const PointColumns& sorted,
                          const PointCloudInfo& info) {
  const StartMessage start = receive_start(ranks, part.levels.at(0).size());
  const uint32_t depth = start.depth;  // the levels rank 0 writes: none of this rank's nodes lies deeper
  PointHierarchy mine;
  std::vector<NodePoints> sources;
  part_nodes(part, start.absorbed, mine.nodes, sources);
  std::vector<uint64_t> order;
  expand_order(sources, part.reps, order);
  const PointColumns points = gather_columns(sorted, order, info.extra_bytes);
  order = {};
  // Its points of each level: where they start in node order and how many.
  std::vector<uint64_t> first(depth + 1, 0), count(depth + 1, 0);
  uint64_t at = 0;
  for (const PointNode& n : mine.nodes) {
    if (n.level > depth) throw Error("points: internal error: a rank's node lies below the hierarchy's depth");
    if (count[n.level] == 0) first[n.level] = at;
    count[n.level] += n.point_count;
    at += n.point_count;
  }
  uint64_t sent = 0;
  for (const Column& c : columns_of(info))
    for (uint32_t l = part.top_level; l <= depth; ++l)
      sent += pass_to_lead(ranks, column_data(points, c.kind) + first[l] * c.per_point, count[l] * c.per_point, nullptr);
  return sent;
}

}  // namespace mv::points
