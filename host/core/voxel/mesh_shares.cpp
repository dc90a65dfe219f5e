#include "voxel/mesh_shares.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "common/morton.h"
#include "megavox/error.h"
#include "voxel/cube_hooks.h"

namespace mv {

namespace {

template <class T>
void put_value(std::vector<uint8_t>& out, const T& v) {
  const auto* p = reinterpret_cast<const uint8_t*>(&v);
  out.insert(out.end(), p, p + sizeof v);
}

template <class T>
T value_at(const std::vector<uint8_t>& in, size_t& at) {
  if (in.size() - at < sizeof(T)) throw Error("internal error: a rank's share of the mesh is cut short");
  T v;
  std::memcpy(&v, in.data() + at, sizeof v);
  at += sizeof v;
  return v;
}

}  // namespace

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
  std::vector<uint8_t> bytes;
  put_value(bytes, uint8_t{ok});
  put_value(bytes, mine.triangles);
  for (double v : {mine.area, mine.shadow_area, mine.dominant_area}) put_value(bytes, v);
  for (int a = 0; a < 3; ++a) put_value(bytes, mine.bounds.lo[a]), put_value(bytes, mine.bounds.hi[a]);
  std::vector<uint8_t> bits((used.size() + 7) / 8, 0);
  for (size_t i = 0; i < used.size(); ++i)
    if (used[i]) bits[i / 8] |= static_cast<uint8_t>(1u << (i % 8));
  bytes.insert(bytes.end(), bits.begin(), bits.end());
  const RankBytes all = ranks.all_gather(bytes);
  for (const auto& b : all)
    if (b.empty() || b[0] == 0) return false;
  std::vector<uint8_t> any(bits.size(), 0);
  for (const auto& b : all) {  // in rank order: every rank sums the same way
    size_t at = 1;
    s.triangles += value_at<uint64_t>(b, at);
    s.area += value_at<double>(b, at);
    s.shadow_area += value_at<double>(b, at);
    s.dominant_area += value_at<double>(b, at);
    for (int a = 0; a < 3; ++a) {
      const auto lo = value_at<double>(b, at);
      const auto hi = value_at<double>(b, at);
      s.bounds.lo[a] = std::min(s.bounds.lo[a], lo);
      s.bounds.hi[a] = std::max(s.bounds.hi[a], hi);
    }
    if (b.size() - at != any.size()) throw Error("internal error: the ranks read meshes of different vertex counts");
    for (size_t i = 0; i < any.size(); ++i) any[i] |= b[at + i];
  }
  for (uint8_t byte : any) s.vertices += static_cast<uint64_t>(__builtin_popcount(byte));
  s.face_shares = true;
  s.bytes_read = mesh.bytes_spanned();
  return true;
}

std::vector<uint64_t> send_triangles_to_cube_owners(const RankCollectives& ranks, TriangleBuckets& buckets,
                                                    uint32_t per_axis, uint64_t& triangles, uint64_t& exchanged) {
  std::vector<uint64_t> estimates = cube_voxel_estimates(buckets, per_axis);
  std::vector<uint8_t> mine;
  put_value(mine, triangles);
  for (uint64_t e : estimates) put_value(mine, e);
  std::fill(estimates.begin(), estimates.end(), 0);
  triangles = 0;
  for (const auto& b : ranks.all_gather(mine)) {
    size_t at = 0;
    triangles += value_at<uint64_t>(b, at);
    for (uint64_t& e : estimates) e += value_at<uint64_t>(b, at);
  }
  const std::vector<int> owner = deal_in_order(estimates, ranks.size);
  // To each owner: per cube, its Morton index, its floats, then the floats.
  RankBytes parts(static_cast<size_t>(ranks.size));
  for (uint64_t c = 0; c < owner.size(); ++c) {
    if (owner[c] == ranks.rank) continue;
    const std::vector<float> tris =
        buckets.take(mv_morton3_64_axis(c, 0), mv_morton3_64_axis(c, 1), mv_morton3_64_axis(c, 2));
    if (tris.empty()) continue;
    std::vector<uint8_t>& out = parts[static_cast<size_t>(owner[c])];
    put_value(out, c);
    put_value(out, uint64_t{tris.size()});
    const auto* p = reinterpret_cast<const uint8_t*>(tris.data());
    out.insert(out.end(), p, p + tris.size() * sizeof(float));
  }
  for (size_t r = 0; r < parts.size(); ++r) exchanged += static_cast<int>(r) == ranks.rank ? 0 : parts[r].size();
  const RankBytes got = ranks.all_to_all(std::move(parts));
  std::vector<float> tris;
  for (size_t r = 0; r < got.size(); ++r) {
    const std::vector<uint8_t>& b = got[r];
    if (static_cast<int>(r) != ranks.rank) exchanged += b.size();
    for (size_t at = 0; at < b.size();) {
      const uint64_t c = value_at<uint64_t>(b, at), floats = value_at<uint64_t>(b, at);
      if (c >= owner.size() || owner[c] != ranks.rank || (b.size() - at) / sizeof(float) < floats)
        throw Error("internal error: a rank sent triangles of a cube this rank does not make");
      tris.resize(floats);
      std::memcpy(tris.data(), b.data() + at, floats * sizeof(float));
      at += floats * sizeof(float);
      buckets.put(mv_morton3_64_axis(c, 0), mv_morton3_64_axis(c, 1), mv_morton3_64_axis(c, 2), tris);
    }
  }
  return estimates;
}

}  // namespace mv
