#include "voxel/mesh_shares.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/morton.h"
#include "megavox/error.h"
#include "megavox/rank_message.h"
#include "io/memory_mesh.h"
#include "voxel/cube_hooks.h"

namespace mv {

namespace {

// Collective. This rank's share of the faces (`indices`) with the vertices they use, fetched from the ranks that
// read them: rank r reads vertices [V r / N, V (r + 1) / N) by offset. `owned_used` gets how many of those some
// rank's faces use. 16-bit colours keep their high byte unless every vertex's fit 8 bits, as one reader decides.
std::shared_ptr<MeshShare> fetch_vertices(const RankCollectives& ranks, io::MeshSource& mesh,
                                          std::vector<uint32_t>&& indices, uint64_t first_triangle,
                                          uint64_t& owned_used, uint64_t& exchanged) {
  const uint64_t count = mesh.vertex_count();
  const auto n = static_cast<size_t>(ranks.size);
  const auto start = [&](size_t r) { return static_cast<uint64_t>((unsigned __int128)count * r / n); };
  std::vector<uint32_t> needed = indices;
  std::sort(needed.begin(), needed.end());
  needed.erase(std::unique(needed.begin(), needed.end()), needed.end());
  RankBytes asks(n);
  size_t owner = 0;
  for (size_t i = 0; i < needed.size(); ++i) {
    while (needed[i] >= start(owner + 1)) ++owner;
    const auto* p = reinterpret_cast<const uint8_t*>(&needed[i]);
    asks[owner].insert(asks[owner].end(), p, p + 4);
  }
  exchanged += bytes_of_others(asks, ranks.rank);
  const RankBytes asked = ranks.all_to_all(std::move(asks));
  exchanged += bytes_of_others(asked, ranks.rank);

  const size_t me = static_cast<size_t>(ranks.rank);
  const uint64_t lo = start(me), hi = start(me + 1);
  std::vector<float> xyz;
  std::vector<uint16_t> rgb;
  mesh.read_vertex_range(lo, hi, xyz, rgb);
  const int bits = mesh.colour_bits();
  MessageWriter narrow;
  narrow.put<uint8_t>(std::all_of(rgb.begin(), rgb.end(), [](uint16_t c) { return c < 256; }));
  int shift = 0;
  for (const std::vector<uint8_t>& b : ranks.all_gather(narrow.bytes))
    if (bits == 16 && MessageReader(b).get<uint8_t>() == 0) shift = 8;
  std::vector<bool> used(hi - lo, false);
  RankBytes replies(n);
  for (size_t r = 0; r < n; ++r) {
    MessageWriter w;
    for (size_t at = 0; at + 4 <= asked[r].size(); at += 4) {
      uint32_t id = 0;
      std::memcpy(&id, asked[r].data() + at, 4);
      if (id < lo || id >= hi) throw Error("internal error: a rank asked for a vertex another rank reads");
      const uint64_t k = id - lo;
      used[k] = true;
      for (int a = 0; a < 3; ++a) w.put(xyz[3 * k + a]);
      if (bits)
        w.put(uint32_t(rgb[3 * k] >> shift) | uint32_t(rgb[3 * k + 1] >> shift) << 8 | uint32_t(rgb[3 * k + 2] >> shift) << 16);
    }
    replies[r] = std::move(w.bytes);
  }
  owned_used = static_cast<uint64_t>(std::count(used.begin(), used.end(), true));
  xyz = {};
  rgb = {};
  exchanged += bytes_of_others(replies, ranks.rank);
  const RankBytes got = ranks.all_to_all(std::move(replies));
  exchanged += bytes_of_others(got, ranks.rank);

  auto share = std::make_shared<MeshShare>();
  share->first_triangle = first_triangle;
  share->positions.reserve(3 * needed.size());
  if (bits) share->colours.reserve(needed.size());
  for (size_t r = 0; r < n; ++r)  // needed is in owner order, each owner's ids ascending: the replies follow it
    for (MessageReader in(got[r]); in.left() > 0;) {
      for (int a = 0; a < 3; ++a) share->positions.push_back(in.get<float>());
      if (bits) share->colours.push_back(in.get<uint32_t>());
    }
  if (share->positions.size() != 3 * needed.size()) throw Error("internal error: the ranks sent too few vertices");
  for (uint32_t& i : indices)
    i = static_cast<uint32_t>(std::lower_bound(needed.begin(), needed.end(), i) - needed.begin());
  share->indices = std::move(indices);
  return share;
}

}  // namespace

bool survey_face_shares(const RankCollectives& ranks, io::MeshSource& mesh, size_t batch, MeshSurvey& s) {
  MeshSurvey mine;
  std::vector<bool> used;
  std::vector<uint32_t> indices;  // with deferred vertices: the share's faces, read whole before the fetch
  bool ok = false;
  try {
    if (mesh.select_face_share(ranks.rank, ranks.size)) {
      if (mesh.vertices_deferred()) {
        for (std::vector<uint32_t> batch_indices; mesh.next_triangles(batch_indices, batch);)
          indices.insert(indices.end(), batch_indices.begin(), batch_indices.end());
      } else {
        survey_faces(mesh, batch, mine, used);
        survey_used_vertices(mesh.positions(), used, mine);
      }
      ok = true;
    }
  } catch (const Error&) {  // e.g. a face that is not a triangle: every rank reads the whole mesh, and says why
  }
  // Whether every rank read its share so, and alike (vertices deferred or not): else each reads the whole mesh.
  MessageWriter state;
  state.put(uint8_t{ok});
  state.put(uint8_t{mesh.vertices_deferred()});
  for (const auto& b : ranks.all_gather(state.bytes)) {
    MessageReader in(b);
    if (in.get<uint8_t>() == 0 || in.get<uint8_t>() != uint8_t{mesh.vertices_deferred()}) return false;
  }
  uint64_t owned_used = 0;
  if (mesh.vertices_deferred()) {
    std::shared_ptr<const MeshShare> share = fetch_vertices(ranks, mesh, std::move(indices), mesh.first_triangle(),
                                                            owned_used, s.bytes_exchanged);
    auto local = io::memory_mesh(share->positions, share->indices, "a share of the mesh", share->colours);
    survey_faces(*local, batch, mine, used);
    survey_used_vertices(local->positions(), used, mine);
    used.clear();  // the ranks count the vertices they read instead
    s.share = std::move(share);
  }
  // This rank's survey: the counts and sums, the bounds, then the used vertices: as bits, or the count of those
  // it read.
  MessageWriter w;
  w.put(mine.triangles);
  for (double v : {mine.area, mine.shadow_area, mine.dominant_area}) w.put(v);
  for (int a = 0; a < 3; ++a) w.put(mine.bounds.lo[a]), w.put(mine.bounds.hi[a]);
  w.put(owned_used);
  std::vector<uint8_t> bits((used.size() + 7) / 8, 0);
  for (size_t i = 0; i < used.size(); ++i)
    if (used[i]) bits[i / 8] |= static_cast<uint8_t>(1u << (i % 8));
  w.put_all(bits);
  const RankBytes all = ranks.all_gather(w.bytes);
  std::vector<uint8_t> any(bits.size(), 0);
  for (const auto& b : all) {  // in rank order: every rank sums the same way
    MessageReader in(b);
    s.triangles += in.get<uint64_t>();
    s.area += in.get<double>();
    s.shadow_area += in.get<double>();
    s.dominant_area += in.get<double>();
    for (int a = 0; a < 3; ++a) {
      const double lo = in.get<double>(), hi = in.get<double>();
      s.bounds.lo[a] = std::min(s.bounds.lo[a], lo);
      s.bounds.hi[a] = std::max(s.bounds.hi[a], hi);
    }
    s.vertices += in.get<uint64_t>();
    in.get_all(bits);
    if (bits.size() != any.size()) throw Error("internal error: the ranks read meshes of different vertex counts");
    for (size_t i = 0; i < any.size(); ++i) any[i] |= bits[i];
  }
  for (uint8_t byte : any) s.vertices += static_cast<uint64_t>(__builtin_popcount(byte));
  s.face_shares = true;
  s.bytes_read = mesh.bytes_spanned();
  return true;
}

std::vector<uint64_t> send_triangles_to_cube_owners(const RankCollectives& ranks, TriangleBuckets& buckets,
                                                    uint32_t per_axis, uint64_t& triangles, uint64_t& exchanged) {
  std::vector<uint64_t> estimates = cube_voxel_estimates(buckets, per_axis);
  estimates.push_back(triangles);  // summed with them, then taken off
  estimates = sum_over_ranks(ranks, estimates);
  triangles = estimates.back();
  estimates.pop_back();
  const std::vector<int> owner = deal_in_order(estimates, ranks.size);
  // To each owner: per cube, its Morton index, then its triangles' floats.
  std::vector<MessageWriter> to(static_cast<size_t>(ranks.size));
  for (uint64_t c = 0; c < owner.size(); ++c) {
    if (owner[c] == ranks.rank) continue;
    const std::vector<float> tris =
        buckets.take(mv_morton3_64_axis(c, 0), mv_morton3_64_axis(c, 1), mv_morton3_64_axis(c, 2));
    if (tris.empty()) continue;
    to[static_cast<size_t>(owner[c])].put(c);
    to[static_cast<size_t>(owner[c])].put_all(tris);
  }
  RankBytes parts;
  for (MessageWriter& m : to) parts.push_back(std::move(m.bytes));
  exchanged += bytes_of_others(parts, ranks.rank);
  const RankBytes got = ranks.all_to_all(std::move(parts));
  exchanged += bytes_of_others(got, ranks.rank);
  std::vector<float> tris;
  for (size_t r = 0; r < got.size(); ++r) {
    for (MessageReader in(got[r]); in.left() > 0;) {
      const uint64_t c = in.get<uint64_t>();
      if (c >= owner.size() || owner[c] != ranks.rank)
        throw Error("internal error: a rank sent triangles of a cube this rank does not make");
      in.get_all(tris);
      buckets.put(mv_morton3_64_axis(c, 0), mv_morton3_64_axis(c, 1), mv_morton3_64_axis(c, 2), tris);
    }
  }
  return estimates;
}

}  // namespace mv
