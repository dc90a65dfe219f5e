// A build's plan (megavox/build.h BuildPlan) from what one pass over the mesh's faces finds, before the heavy
// work: the grid, in core or in cubes, and estimates of the voxels, the output and the memory.
#pragma once
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "megavox/build.h"
#include "megavox/grid.h"
#include "io/mesh_source.h"

namespace mv {

// A rank's share of a mesh whose vertices the ranks read in shares (voxel/mesh_shares.h): its faces' triangles
// as indices into its own table of the vertices they use (positions, 8-bit colours), and its first face's place
// in the file's.
struct MeshShare {
  std::vector<float> positions;
  std::vector<uint32_t> indices, colours;
  uint64_t first_triangle = 0;
};

// What a pass over a mesh's faces finds: the bounds of the vertices they use and the surface they make.
struct MeshSurvey {
  Bounds bounds;
  uint64_t triangles = 0;
  uint64_t vertices = 0;
  double area = 0;
  // Sums over the triangles of area * (|nx| + |ny| + |nz|), their shadows on the three axis planes, and of
  // area * max(|nx|, |ny|, |nz|), the shadow on each one's dominant plane: over a voxel's face area, about the
  // voxels a conservative and a thin voxelization give.
  double shadow_area = 0;
  double dominant_area = 0;
  void add_triangle(const float* a, const float* b, const float* c);
  bool face_shares = false;  // over ranks: each rank read a share of the faces (voxel/mesh_shares.h)
  uint64_t bytes_read = 0;   // then: the file bytes this rank's share spans (the vertices and its faces)
  uint64_t bytes_exchanged = 0;        // and what fetching its faces' vertices moved
  std::shared_ptr<const MeshShare> share;  // set where the vertices were read in shares too
  // The surveyed source, rewound, where it can walk its faces again without reading the file (else: none, and the
  // walk opens the file anew).
  std::shared_ptr<io::MeshSource> source;
};

// The faces `mesh` delivers (batches of `batch` triangles) into `s`, marking the vertices they use in `used`
// (one flag per vertex); then the used vertices' bounds and count into `s`.
void survey_faces(io::MeshSource& mesh, size_t batch, MeshSurvey& s, std::vector<bool>& used);
void survey_used_vertices(std::span<const float> positions, const std::vector<bool>& used, MeshSurvey& s);

// Host and device memory the estimates are checked against (0: not checked).
struct PlanBudgets {
  uint64_t host = 0;
  uint64_t device = 0;
};

BuildPlan plan_mesh_build(const BuildOptions& o, const MeshSurvey& survey, const GridTransform& grid,
                          const PlanBudgets& budgets);
// A .vdb: its voxels are read, so counted, not estimated.
BuildPlan plan_vdb_build(const BuildOptions& o, uint64_t voxels, const GridTransform& grid, const PlanBudgets& budgets);

}  // namespace mv
