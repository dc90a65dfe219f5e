#include "point_ranks_tiles.h"

#include <cstring>
#include <exception>
#include <string>

#include "megavox/error.h"
#include "megavox/rank_message.h"
#include "point_gather.h"

namespace mv::points {

io::Tiles3dShare lead_tiles_share(const RankCollectives& ranks, const PointHierarchy& h, const std::vector<int>& owner,
                                  uint32_t top_level, std::vector<std::vector<bool>> absorbed, uint64_t& tiles) {
  io::Tiles3dShare share;
  share.elsewhere.resize(h.nodes.size());
  tiles = 0;
  for (size_t i = 0; i < h.nodes.size(); ++i) {
    const PointNode& n = h.nodes[i];
    if (n.level >= top_level) {
      const uint64_t cell = (n.code ^ (uint64_t{1} << (3 * n.level))) >> (3 * (n.level - top_level));
      share.elsewhere[i] = owner.at(cell) != 0;
    }
    if (!share.elsewhere[i] && n.point_count) ++tiles;
  }
  share.start = [&ranks, absorbed = std::move(absorbed)](const std::string& tmp, int colour_shift) {
    if (ranks.sleepy_barrier) ranks.sleepy_barrier();  // the others wait there
    RankBytes parts(static_cast<size_t>(ranks.size));
    for (int r = 1; r < ranks.size; ++r) {
      MessageWriter m;
      m.put_text(tmp);
      m.put(static_cast<uint8_t>(colour_shift));
      std::vector<uint8_t> flags;
      for (bool a : absorbed[static_cast<size_t>(r)]) flags.push_back(a ? 1 : 0);
      m.put_all(flags);
      parts[static_cast<size_t>(r)] = std::move(m.bytes);
    }
    ranks.all_to_all(std::move(parts));
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
  if (ranks.sleepy_barrier) ranks.sleepy_barrier();  // asleep while rank 0 joins the parts and checks the tileset
  const RankBytes got = ranks.all_to_all(RankBytes(static_cast<size_t>(ranks.size)));
  std::string failure;
  uint64_t tiles = 0;
  try {
    MessageReader in(got[0]);
    const std::string tmp = in.text();
    const int colour_shift = in.get<uint8_t>();
    std::vector<uint8_t> flags;
    in.get_all(flags);
    if (flags.size() != part.levels.at(0).size()) throw Error("points: internal error: rank 0's tile message does not fit");
    const std::vector<bool> absorbed(flags.begin(), flags.end());
    std::vector<NodePoints> sources;
    part_nodes(part, absorbed, grid.nodes, sources);
    std::vector<uint64_t> order;
    expand_order(sources, part.reps, order);
    grid.points = gather_columns(sorted, order, grid.source.extra_bytes);
    io::write_3dtiles_part(tmp, grid, options, lo, hi, colour_shift);
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
