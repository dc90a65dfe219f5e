#include "point_ranks_tiles.h"

#include <cstring>
#include <exception>
#include <string>

#include "megavox/error.h"
#include "point_gather.h"

namespace mv::points {

namespace {

void put_text(std::vector<uint8_t>& out, const std::string& s) {
  const uint64_t n = s.size();
  const auto* p = reinterpret_cast<const uint8_t*>(&n);
  out.insert(out.end(), p, p + 8);
  out.insert(out.end(), s.begin(), s.end());
}

std::string text_at(const std::vector<uint8_t>& in, size_t& at) {
  uint64_t n = 0;
  if (in.size() - at < 8) throw Error("points: internal error: a rank's message is cut short");
  std::memcpy(&n, in.data() + at, 8);
  at += 8;
  if (in.size() - at < n) throw Error("points: internal error: a rank's message is cut short");
  std::string s(reinterpret_cast<const char*>(in.data() + at), n);
  at += n;
  return s;
}

}  // namespace

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
      std::vector<uint8_t>& m = parts[static_cast<size_t>(r)];
      put_text(m, tmp);
      m.push_back(static_cast<uint8_t>(colour_shift));
      for (bool a : absorbed[static_cast<size_t>(r)]) m.push_back(a ? 1 : 0);
    }
    ranks.all_to_all(std::move(parts));
  };
  share.finish = [&ranks] {
    const RankBytes done = ranks.all_gather({1});
    for (int r = 1; r < ranks.size; ++r) {
      const std::vector<uint8_t>& d = done[static_cast<size_t>(r)];
      if (d.empty() || d[0] != 1) {
        size_t at = 1;
        throw Error("rank " + std::to_string(r) + " could not write its tiles: " + (d.size() > 1 ? text_at(d, at) : ""));
      }
    }
  };
  return share;
}

uint64_t write_part_tiles(const RankCollectives& ranks, const OmicronPart& part, const PointColumns& sorted,
                          PointHierarchy grid, const io::Tiles3dOptions& options, const int64_t lo[3],
                          const int64_t hi[3]) {
  if (ranks.sleepy_barrier) ranks.sleepy_barrier();  // asleep while rank 0 joins the parts and checks the tileset
  const RankBytes got = ranks.all_to_all(RankBytes(static_cast<size_t>(ranks.size)));
  const std::vector<uint8_t>& m = got[0];
  std::vector<uint8_t> done{1};
  uint64_t tiles = 0;
  try {
    size_t at = 0;
    const std::string tmp = text_at(m, at);
    if (m.size() - at != 1 + part.levels.at(0).size()) throw Error("points: internal error: rank 0's tile message does not fit");
    const int colour_shift = m[at++];
    const std::vector<bool> absorbed(m.begin() + static_cast<std::ptrdiff_t>(at), m.end());
    std::vector<NodePoints> sources;
    part_nodes(part, absorbed, grid.nodes, sources);
    std::vector<uint64_t> order;
    expand_order(sources, part.reps, order);
    grid.points = gather_columns(sorted, order, grid.source.extra_bytes);
    io::write_3dtiles_part(tmp, grid, options, lo, hi, colour_shift);
    for (const PointNode& n : grid.nodes) tiles += n.point_count ? 1 : 0;
  } catch (const std::exception& e) {  // rank 0 says so and removes the folder; this rank must not end the run first
    done = {0};
    put_text(done, e.what());
  }
  ranks.all_gather(done);
  return tiles;
}

}  // namespace mv::points
