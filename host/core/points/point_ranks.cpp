// `mpirun -np N megavox points build`: a point build spread over ranks (docs/distributed.md "Point clouds").
// Each rank reads a contiguous slice of the input's points, the ranks agree on the cube, sort their slices by
// Morton code and deal whole cells of one level (the top level) to ranks in Morton order; each rank builds its
// cells' subtrees bottom-up, and rank 0 joins them and makes the levels above. Each rank keeps its nodes' points
// until they are written: its tiles, or handed to rank 0 as it writes the .mvx. The bytes are those of one
// process: equal codes keep their input order (slices are in input order and every sort is stable), and a node
// is a function of its subtree's points alone.
#include "point_ranks.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <type_traits>

#include "io/point_source.h"
#include "megavox/error.h"
#include "megavox/rank_collectives.h"
#include "megavox/rank_message.h"
#include "omicron.h"
#include "point_gather.h"
#include "point_kernels.h"
#include "point_ranks_mvx.h"
#include "point_ranks_tiles.h"
#include "point_runs.h"
#include "timing.h"

namespace mv::points {

namespace {

static_assert(std::is_trivially_copyable_v<LodNode>);

// The level whose cells are dealt: the shallowest with 64 cells a rank, at most the leaves.
uint32_t dealt_level(uint32_t depth, int ranks) {
  uint32_t level = 1;
  while (level < depth && (uint64_t{1} << (3 * level)) < uint64_t{64} * static_cast<uint64_t>(ranks)) ++level;
  return level;
}

// The positions (in a part's sorted points) of the candidates the levels above its top level are made from:
// every point of its top-level leaves and the representatives of its top-level inner nodes, as sorted runs
// [begin, end) (a leaf's points are one), so that the points they name keep their order.
struct Run {
  uint64_t begin, end;
};
using Runs = std::vector<Run>;
Runs top_candidates(const OmicronPart& part) {
  Runs runs;
  for (const LodNode& n : part.levels.at(0)) {
    if (n.child_mask == 0) {
      runs.push_back({n.first, n.first + n.points});
      continue;
    }
    for (uint64_t k = n.rep_begin; k < n.rep_begin + n.rep_count; ++k) runs.push_back({part.reps[k], part.reps[k] + 1});
  }
  std::sort(runs.begin(), runs.end(), [](const Run& a, const Run& b) { return a.begin < b.begin; });
  Runs merged;
  for (const Run& r : runs) {
    if (!merged.empty() && r.begin <= merged.back().end) merged.back().end = std::max(merged.back().end, r.end);
    else merged.push_back(r);
  }
  return merged;
}

// A part whose sender sent only the points in `runs` (top_candidates): its positions become places among
// them, in the same order. The join reads only those of its top level; the nodes below are the sender's to
// write, and their positions only keep their order.
void to_positions_sent(OmicronPart& part, const Runs& runs) {
  std::vector<uint64_t> before(runs.size() + 1, 0);  // points sent before each run
  for (size_t k = 0; k < runs.size(); ++k) before[k + 1] = before[k] + (runs[k].end - runs[k].begin);
  const auto place = [&](uint64_t q) {
    const auto after = std::upper_bound(runs.begin(), runs.end(), q, [](uint64_t v, const Run& r) { return v < r.begin; });
    const auto k = static_cast<size_t>(after - runs.begin());  // runs[k - 1] is the last to begin at or before q
    if (k == 0) return uint64_t{0};
    return q < runs[k - 1].end ? before[k - 1] + (q - runs[k - 1].begin) : before[k];
  };
  for (auto& level : part.levels)
    for (LodNode& node : level) node.first = place(node.first);
  for (uint64_t& q : part.reps) q = place(q);
  part.points = before.back();
}

bool wide_colour(const PointColumns& points) {
  return std::any_of(points.rgb.begin(), points.rgb.end(), [](uint16_t v) { return v > 255; });
}

}  // namespace

PointHierarchy build_over_ranks(Device& dev, const PointFileOptions& o, const RankCollectives& ranks,
                                PointFileReport& report, const Progress& progress,
                                const std::function<void(const PointCloudInfo&)>& check_fits, io::Tiles3dShare* tiles,
                                PointsElsewhere* points_share) {
  const bool lead = ranks.rank == 0;
  if (!(o.format == PointOutput::tiles3d ? tiles != nullptr : points_share != nullptr))
    throw Error("points: internal error: a build over ranks without its output's share");
  auto t0 = std::chrono::steady_clock::now();
  io::PointReadOptions ro;
  ro.carry_extra_bytes = o.carry_extra_bytes;
  ro.bounds = o.bounds;
  // A PLY cloud's grid comes from its largest |coordinate|: each rank finds its slice's (where it can seek to it)
  // and the ranks agree on the largest. Its slice is [lo, hi) of the records, below.
  ro.slice_part = ranks.rank;
  ro.slice_parts = ranks.size;
  ro.agree_extent = [&ranks](double mine) {
    MessageWriter w;
    w.put(mine);
    double most = mine;
    for (const std::vector<uint8_t>& b : ranks.all_gather(w.bytes)) most = std::max(most, MessageReader(b).get<double>());
    return most;
  };
  std::unique_ptr<io::PointSource> src = io::open_points(o.input, ro);
  const PointCloudInfo info = src->info();
  report.input_format = info.format;
  if (lead && check_fits) check_fits(info);

  // This rank's slice of the file's point records, in input order (with --bounds, the points of it inside the
  // box: the slices together are the points one process reads, in its order).
  const uint64_t declared = info.points;
  const uint64_t lo = static_cast<uint64_t>((unsigned __int128)declared * ranks.rank / ranks.size);
  const uint64_t hi = static_cast<uint64_t>((unsigned __int128)declared * (ranks.rank + 1) / ranks.size);
  const uint64_t unread = src->skip(lo);
  PointColumns mine;
  mine.reserve_more(o.bounds ? 0 : hi - lo, info.attributes, info.extra_bytes);
  while (src->records_read() < hi &&
         src->next(mine, static_cast<size_t>(std::min<uint64_t>(hi - src->records_read(), 1 << 20))))
    if (progress && lead) progress("read", double(src->records_read() - lo) / double(std::max<uint64_t>(1, hi - lo)));
  if (src->records_read() != hi)
    throw Error(o.input + ": the file holds " + std::to_string(src->records_read()) + " points where its header declares " +
                std::to_string(declared));
  // The share of the file the reader went through: all of it where a PLY reader cannot seek to its slice.
  const bool whole = src->read_whole_file();
  src.reset();
  std::error_code size_error;
  const uint64_t file_bytes = std::filesystem::file_size(o.input, size_error);
  report.ranks.points_read = hi - lo;
  report.ranks.bytes_read = declared == 0 || whole ? file_bytes
                                                   : static_cast<uint64_t>((unsigned __int128)file_bytes * (hi - unread) / declared);
  report.read_seconds = seconds_since(t0);

  // The cube of every rank's points: the same on every rank.
  t0 = std::chrono::steady_clock::now();
  int64_t box[7] = {INT64_MAX, INT64_MAX, INT64_MAX, INT64_MIN, INT64_MIN, INT64_MIN, static_cast<int64_t>(mine.size())};
  if (mine.size()) point_bounds(dev, mine.xyz, box, box + 3);
  MessageWriter box_message;
  for (int64_t v : box) box_message.put(v);
  int64_t lo3[3] = {INT64_MAX, INT64_MAX, INT64_MAX}, hi3[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
  uint64_t n = 0;
  for (const std::vector<uint8_t>& b : ranks.all_gather(box_message.bytes)) {
    MessageReader in(b);
    int64_t other[7];
    for (int64_t& v : other) v = in.get<int64_t>();
    for (int a = 0; a < 3; ++a) lo3[a] = std::min(lo3[a], other[a]), hi3[a] = std::max(hi3[a], other[3 + a]);
    n += static_cast<uint64_t>(other[6]);
  }
  if (n == 0) throw Error(o.input + ": the cloud has no points");
  const PointCube cube = cube_of_bounds(lo3, hi3);
  OmicronRule rule;
  rule.depth = o.build.depth ? o.build.depth : point_depth_for(n, o.build.max_node_points);
  rule.max_node_points = o.build.max_node_points;
  rule.grid_bits = o.build.grid_bits;
  rule.top_level = dealt_level(rule.depth, ranks.size);
  const uint32_t cell_shift = 3 * (21 - rule.top_level);

  // Count the slice's points per cell of the top level; deal the cells in Morton order by count.
  std::vector<uint64_t> codes;
  std::vector<uint32_t> order;
  if (mine.size()) point_codes(dev, mine.xyz, cube, codes, order);
  std::vector<uint64_t> cells(uint64_t{1} << (3 * rule.top_level), 0);
  for (uint64_t c : codes) ++cells[c >> cell_shift];
  cells = sum_over_ranks(ranks, cells);
  const std::vector<int> owner = deal_in_order(cells, ranks.size);

  // Each point goes to its cell's rank as a record (code, then every column), in input order: a stable
  // partition, so that the ranks' runs in rank order are the input order again.
  const RecordLayout layout = record_layout(info);
  RankBytes parts(static_cast<size_t>(ranks.size));
  {
    std::vector<uint64_t> at(static_cast<size_t>(ranks.size), 0);
    for (uint64_t c : codes) ++at[static_cast<size_t>(owner[c >> cell_shift])];
    for (size_t r = 0; r < parts.size(); ++r) parts[r].resize(at[r] * layout.bytes), at[r] = 0;
    for (uint64_t i = 0; i < codes.size(); ++i) {
      const size_t r = static_cast<size_t>(owner[codes[i] >> cell_shift]);
      pack(layout, mine, i, codes[i], parts[r].data() + at[r]++ * layout.bytes);
    }
  }
  mine = PointColumns();
  codes = {};
  order = {};
  report.ranks.bytes_exchanged += bytes_of_others(parts, ranks.rank);
  RankBytes got = ranks.all_to_all(std::move(parts));
  report.ranks.bytes_exchanged += bytes_of_others(got, ranks.rank);

  // The received runs in rank order, stably sorted: equal codes keep their input order.
  uint64_t m = 0;
  for (const auto& b : got) m += b.size() / layout.bytes;
  if (m > UINT32_MAX) throw Error("points build: a rank's share is over 2^32 points; run it over more ranks");
  // record i of the runs in rank order: got[r] at i - first[r], for the r with first[r] <= i < first[r + 1]
  std::vector<uint64_t> first(got.size() + 1, 0);
  for (size_t r = 0; r < got.size(); ++r) first[r + 1] = first[r] + got[r].size() / layout.bytes;
  const auto record = [&](uint64_t i) {
    const size_t r = static_cast<size_t>(std::upper_bound(first.begin(), first.end(), i) - first.begin()) - 1;
    return got[r].data() + (i - first[r]) * layout.bytes;
  };
  codes.resize(m);
  order.resize(m);
  for (size_t r = 0; r < got.size(); ++r)
    for (uint64_t i = first[r]; i < first[r + 1]; ++i)
      codes[i] = record_code(got[r].data() + (i - first[r]) * layout.bytes), order[i] = static_cast<uint32_t>(i);
  if (m) report.build.sort = radix_sort(dev, codes, &order);
  report.sort_seconds = seconds_since(t0);
  report.ranks.points_built = m;

  // This rank's subtrees up to the top level, then its part for rank 0: the lists and the sorted records it
  // needs, the points the levels above are made from (top_candidates). Each other rank keeps its points and
  // writes its nodes' tiles, or hands them to rank 0 as it writes the .mvx.
  t0 = std::chrono::steady_clock::now();
  OmicronBuilder builder(dev, rule);
  builder.concatenate(codes, true);
  OmicronPart part = builder.take_part();
  const bool keeps_points = !lead;  // rank 0 gets only the candidates of the others' points
  PointColumns sorted_here = keeps_points ? columns_for(layout, m) : PointColumns();
  if (keeps_points)
    tbb::parallel_for(tbb::blocked_range<uint64_t>(0, m, 1 << 14), [&](const tbb::blocked_range<uint64_t>& r) {
      for (uint64_t i = r.begin(); i < r.end(); ++i) unpack_at(layout, record(order[i]), sorted_here, i);
    });
  const Runs runs = keeps_points ? top_candidates(part) : Runs{{0, m}};
  std::vector<uint64_t> sent;  // the sorted positions of the records sent, when not all
  if (keeps_points)
    for (const Run& r : runs)
      for (uint64_t q = r.begin; q < r.end; ++q) sent.push_back(q);
  const uint64_t records = keeps_points ? sent.size() : m;
  MessageWriter msg;
  msg.put(part.top_level);
  msg.put(part.points);
  for (const auto& level : part.levels) msg.put_all(level);
  msg.put_all(part.reps);
  msg.put<uint8_t>(keeps_points);  // then the positions of the records sent
  if (keeps_points) msg.put_all(runs);
  msg.put<uint8_t>(wide_colour(sorted_here));
  if (!keeps_points) part = OmicronPart();
  const size_t head = msg.bytes.size();
  msg.bytes.resize(head + records * layout.bytes);
  tbb::parallel_for(tbb::blocked_range<uint64_t>(0, records, 1 << 14), [&](const tbb::blocked_range<uint64_t>& r) {
    for (uint64_t i = r.begin(); i < r.end(); ++i)
      std::memcpy(msg.bytes.data() + head + i * layout.bytes, record(order[keeps_points ? sent[i] : i]), layout.bytes);
  });
  got = {};
  codes = {};
  order = {};
  if (!lead) report.ranks.bytes_exchanged += msg.bytes.size();
  const double subtree_seconds = seconds_since(t0);
  RankBytes parts_at_lead = ranks.gather(std::move(msg.bytes));
  report.build_seconds = subtree_seconds;
  PointHierarchy h;
  PointHierarchy grid;  // the hierarchy's grid, without nodes
  grid.source = info;
  for (int a = 0; a < 3; ++a) grid.cube_min[a] = cube.min[a];
  grid.shift = cube.shift;
  grid.grid_bits = rule.grid_bits;
  grid.depth = rule.depth;
  if (!lead) {
    if (o.format == PointOutput::tiles3d)
      report.ranks.tiles_written = write_part_tiles(ranks, part, sorted_here, std::move(grid), tiles_options_of(o), lo3, hi3);
    else
      report.ranks.bytes_exchanged += send_part_points(ranks, part, sorted_here, info);
    return h;
  }
  if (ranks.lead_alone) ranks.lead_alone();
  const uint32_t top = rule.top_level;

  // Rank 0: the parts in rank order are the whole sorted stream; the levels above the top level, as one builder
  // over that stream makes them, then the columns in node order.
  t0 = std::chrono::steady_clock::now();
  if (progress) progress("build", 0.5);
  report.ranks.bytes_exchanged += bytes_of_others(parts_at_lead, 0);
  rule.top_level = 0;
  OmicronBuilder joined(dev, rule);
  struct Received {
    OmicronPart part;
    const uint8_t* records = nullptr;  // part.points of them
  };
  std::vector<Received> received;
  uint64_t held = 0;  // points rank 0 got: its own and the others' candidates
  bool wide = false;  // some point's colour needs 16 bits
  for (std::vector<uint8_t>& bytes : parts_at_lead) {
    MessageReader in(bytes);
    Received got_part;
    OmicronPart& p = got_part.part;
    p.top_level = in.get<uint32_t>();
    p.points = in.get<uint64_t>();
    p.levels.resize(rule.depth + 1 - p.top_level);
    for (auto& level : p.levels) in.get_all(level);
    in.get_all(p.reps);
    if (in.get<uint8_t>()) {  // some of its points: positions count among those sent from here on
      Runs runs;
      in.get_all(runs);
      to_positions_sent(p, runs);
    }
    wide |= in.get<uint8_t>() != 0;
    if (in.left() != p.points * layout.bytes) throw Error("points: internal error: a rank's part does not hold its points");
    got_part.records = in.at;
    held += p.points;
    received.push_back(std::move(got_part));
  }
  if (held > n) throw Error("points: internal error: the ranks' parts hold more than every point");
  std::vector<uint64_t> all_codes(held);
  PointColumns sorted = columns_for(layout, held);
  std::vector<uint64_t> top_start;  // per rank: where its top-level nodes start in the joined list
  uint64_t joined_points = 0;
  for (size_t r = 0; r < received.size(); ++r) {
    top_start.push_back(joined.level(top).size());
    const uint64_t count = received[r].part.points;
    const uint8_t* records = received[r].records;
    joined.join(std::move(received[r].part), joined_points);
    tbb::parallel_for(tbb::blocked_range<uint64_t>(0, count, 1 << 14), [&](const tbb::blocked_range<uint64_t>& b) {
      for (uint64_t i = b.begin(); i < b.end(); ++i) {
        const uint8_t* rec = records + i * layout.bytes;
        all_codes[joined_points + i] = record_code(rec);
        unpack_at(layout, rec, sorted, joined_points + i);
      }
    });
    joined_points += count;
    parts_at_lead[r] = {};
  }
  top_start.push_back(joined.level(top).size());
  joined.finish_join(all_codes);
  all_codes = {};
  std::vector<NodePoints> sources;
  joined.assemble(h.nodes, sources, h.nodes_per_level);
  // which of each rank's top-level nodes the join absorbed into a leaf above
  std::vector<std::vector<bool>> absorbed(static_cast<size_t>(ranks.size));
  for (size_t r = 0; r < absorbed.size(); ++r)
    for (uint64_t k = top_start[r]; k < top_start[r + 1]; ++k) absorbed[r].push_back(joined.level(top)[k].absorbed);
  const bool tileset = o.format == PointOutput::tiles3d;
  std::vector<bool> elsewhere;
  if (tileset) {
    *tiles = lead_tiles_share(ranks, h, owner, top, std::move(absorbed), report.ranks.tiles_written);
    std::copy(lo3, lo3 + 3, tiles->lo);
    std::copy(hi3, hi3 + 3, tiles->hi);
    tiles->wide_colour = wide || wide_colour(sorted);
    elsewhere = tiles->elsewhere;
  } else {
    *points_share = lead_points_share(ranks, h, owner, top, std::move(absorbed), report.ranks.bytes_exchanged);
    elsewhere = points_share->elsewhere;
  }
  // Only the nodes rank 0 holds keep their points, in node order. A tile's points start at first_point of
  // those; a .mvx's node table keeps where they lie among every node's.
  std::vector<NodePoints> here;
  uint64_t at = 0;
  for (size_t i = 0; i < h.nodes.size(); ++i) {
    if (elsewhere[i]) continue;
    here.push_back(sources[i]);
    if (tileset) h.nodes[i].first_point = at;
    at += h.nodes[i].point_count;
  }
  sources = std::move(here);
  h.points = gather_node_points(sorted, sources, joined.reps(), info.extra_bytes);
  report.ranks.join_seconds = seconds_since(t0);
  report.build_seconds += report.ranks.join_seconds;

  set_grid_and_counts(h, info, cube, rule.grid_bits, n);
  return h;
}

}  // namespace mv::points
