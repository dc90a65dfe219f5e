#include "point_ranks_tiles.h"

#include <cstring>
#include <exception>
#include <string>

#include "megavox/error.h"
#include "megavox/rank_message.h"
#include "point_gather.h"
#include "point_ranks_mvx.h"

namespace mv::points {

io::Tiles3dShare lead_tiles_share(const RankCollectives& ranks, const PointHierarchy& h, const std::vector<int>& owner,
                                  uint32_t top_level, std::vector<std::vector<bool>> absorbed, uint64_t& tiles) {
  io::Tiles3dShare share;
  share.elsewhere = nodes_elsewhere(h, owner, top_level);
  tiles = 0;
  for (size_t i = 0; i < h.nodes.size(); ++i)
    if (!share.elsewhere[i] && h.nodes[i].point_count) ++tiles;
  const auto depth = static_cast<uint32_t>(h.nodes_per_level.size() - 1);  // h.depth is set after the share
  share.start = [&ranks, depth, absorbed = std::move(absorbed)](const std::string& tmp, int colour_shift) {
    send_start(ranks, StartMessage{tmp, colour_shift, depth, {}}, absorbed);
  };
  share.finish = [&ranks] {
    MessageWriter ok;
    ok.put_text("");
    const RankBytes done = ranks.all_gather(ok.bytes);
    for (int r = 1; r < ranks.size; ++r) {
      const std::string failure = MessageReader(done[static_cast<size_t>(r)]).text();
      if (!failure.empty()) throw Error("rank " + std::to_string(r) + " could not write its tiles: " + failure);
    }
  };
  return share;
}

uint64_t write_part_tiles(const RankCollectives& ranks, const OmicronPart& part, const PointColumns& sorted,
                          PointHierarchy grid, const io::Tiles3dOptions& options, const int64_t lo[3],
                          const int64_t hi[3]) {
  const StartMessage start = receive_start(ranks, part.levels.at(0).size());  // after rank 0 checked the tileset
  std::string failure;
  uint64_t tiles = 0;
  try {
    std::vector<NodePoints> sources;
    part_nodes(part, start.absorbed, grid.nodes, sources);
    std::vector<uint64_t> order;
    expand_order(sources, part.reps, order);
    grid.points = gather_columns(sorted, order, grid.source.extra_bytes);
    io::write_3dtiles_part(start.tmp, grid, options, lo, hi, start.colour_shift);
    for (const PointNode& n : grid.nodes) tiles += n.point_count ? 1 : 0;
  } catch (const std::exception& e) {  // rank 0 says so and removes the folder; this rank must not end the run first
    failure = e.what();
    if (failure.empty()) failure = "unknown error";
  }
  MessageWriter done;
  done.put_text(failure);
  ranks.all_gather(done.bytes);
  return tiles;
}

}  // namespace mv::points
