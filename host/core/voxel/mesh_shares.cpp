#include "voxel/mesh_shares.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/morton.h"
#include "megavox/error.h"
#include "megavox/rank_message.h"
#include "voxel/cube_hooks.h"

namespace mv {

bool survey_face_shares(const RankCollectives& ranks, io::MeshSource& mesh, size_t batch, MeshSurvey& s) {
  MeshSurvey mine;
  std::vector<bool> used;
  bool ok = false;
  try {
    if (mesh.select_face_share(ranks.rank, ranks.size)) {
      survey_faces(mesh, batch, mine, used);
      survey_used_vertices(mesh.positions(), used, mine);
      ok = true;
    }
  } catch (const Error&) {  // e.g. a face that is not a triangle: every rank reads the whole mesh, and says why
  }
  // This rank's survey: ok, the counts and sums, the bounds, then the used vertices as bits.
  MessageWriter w;
  w.put(uint8_t{ok});
  w.put(mine.triangles);
  for (double v : {mine.area, mine.shadow_area, mine.dominant_area}) w.put(v);
  for (int a = 0; a < 3; ++a) w.put(mine.bounds.lo[a]), w.put(mine.bounds.hi[a]);
  std::vector<uint8_t> bits((used.size() + 7) / 8, 0);
  for (size_t i = 0; i < used.size(); ++i)
    if (used[i]) bits[i / 8] |= static_cast<uint8_t>(1u << (i % 8));
  w.put_all(bits);
  const RankBytes all = ranks.all_gather(w.bytes);
  for (const auto& b : all)
    if (MessageReader(b).get<uint8_t>() == 0) return false;
  std::vector<uint8_t> any(bits.size(), 0);
  for (const auto& b : all) {  // in rank order: every rank sums the same way
    MessageReader in(b);
    in.get<uint8_t>();
    s.triangles += in.get<uint64_t>();
    s.area += in.get<double>();
    s.shadow_area += in.get<double>();
    s.dominant_area += in.get<double>();
    for (int a = 0; a < 3; ++a) {
      const double lo = in.get<double>(), hi = in.get<double>();
      s.bounds.lo[a] = std::min(s.bounds.lo[a], lo);
      s.bounds.hi[a] = std::max(s.bounds.hi[a], hi);
    }
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
