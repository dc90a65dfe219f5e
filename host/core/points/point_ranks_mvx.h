// A point build over ranks writing one .mvx (point_ranks.cpp; docs/distributed.md): rank 0 writes the file,
// the other ranks hand it their subtrees' points column by column, level by level, as the file takes them, so
// that no rank holds more than its share. Collective: rank 0's write_mvx_points (with lead_points_share) and
// the other ranks' send_part_points meet; the same bytes as one process.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/mvx.h"
#include "megavox/rank_collectives.h"
#include "omicron.h"

namespace mv::points {

// Per node of h: whether another rank built it (its top-level ancestor's cell, `owner` per cell, is not rank 0's).
std::vector<bool> nodes_elsewhere(const PointHierarchy& h, const std::vector<int>& owner, uint32_t top_level);

// Rank 0, for write_mvx_points: the nodes of h the other ranks hold, and `others`, which takes each rank's bytes
// of a column and level in rank order, counted in `exchanged`. Collective: first sends each rank which of its
// top-level nodes the join absorbed (absorbed[r]).
PointsElsewhere lead_points_share(const RankCollectives& ranks, const PointHierarchy& h, const std::vector<int>& owner,
                                  uint32_t top_level, std::vector<std::vector<bool>> absorbed, uint64_t& exchanged);

// Any other rank, once its part went to rank 0: its part's points (`sorted`: in sorted order) handed to rank 0
// as write_mvx_points asks for them. `info`: the cloud's columns. Returns the bytes sent.
uint64_t send_part_points(const RankCollectives& ranks, const OmicronPart& part, const PointColumns& sorted,
                          const PointCloudInfo& info);

// The start message rank 0 sends every other rank before they write (their tiles, or their points for the
// .mvx): the temporary folder (empty for a .mvx), the colour shift, the hierarchy's depth (its deepest level
// with nodes) and the absorbed flags. Collective.
struct StartMessage {
  std::string tmp;
  int colour_shift = 0;
  uint32_t depth = 0;
  std::vector<bool> absorbed;
};
void send_start(const RankCollectives& ranks, const StartMessage& common, const std::vector<std::vector<bool>>& absorbed);
StartMessage receive_start(const RankCollectives& ranks, size_t top_nodes);

}  // namespace mv::points
