// An out-of-core mesh build over ranks that read shares of the faces (docs/distributed.md): each rank reads a
// share of a binary PLY's triangles by offset and, where the file allows, a share of its vertices, fetching
// from the others the ones its faces use; the ranks combine their surveys, and every cube's triangles go to the
// rank its cube is dealt to before the cubes are made.
#pragma once
#include <cstdint>
#include <vector>

#include "io/mesh_source.h"
#include "megavox/rank_collectives.h"
#include "voxel/build_plan.h"
#include "voxel/triangle_buckets.h"

namespace mv {

// Collective. Surveys this rank's share of `mesh`'s faces (read in batches of `batch`) and combines every rank's
// into `s` (the bounds and counts of the whole mesh; s.face_shares set). A mesh opened with its vertices
// deferred gets them in shares: s.share then holds this rank's faces and the vertices they use. False on every
// rank where some rank cannot read its share so (an ascii or non-triangle file; a fault): `mesh` is then spent
// and `s` partial, and the caller surveys the whole mesh on every rank.
bool survey_face_shares(const RankCollectives& ranks, io::MeshSource& mesh, size_t batch, MeshSurvey& s);

// Collective. Every cube's voxel estimate summed over the ranks (Morton order of the cubes, the same on every
// rank: what the cubes are dealt by), and each cube's triangles moved from every rank to the one it is dealt
// to (deal_in_order). `triangles`: this rank's bucketed triangles in, every rank's out. Adds the bytes sent and
// received to `exchanged`.
std::vector<uint64_t> send_triangles_to_cube_owners(const RankCollectives& ranks, TriangleBuckets& buckets,
                                                    uint32_t per_axis, uint64_t& triangles, uint64_t& exchanged);

}  // namespace mv
