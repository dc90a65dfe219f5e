// Triangles in grid units (9 floats each, or records that start with them) bucketed by the out-of-core cubes their
// bounding boxes meet.
// Buckets stay in host memory up to a budget; past it every bucket is appended to one temporary file
// (created in $TMPDIR or /tmp and unlinked at once, so nothing is left behind) and read back one cube at a
// time. A mesh whose triangles do not fit in RAM still builds; only its vertex positions must.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "io/temp_file.h"

namespace mv {

class TriangleBuckets {
 public:
  // per_axis^3 cubes of `cube` voxels per side; `budget`: bytes of triangles held in memory before spilling;
  // `record_floats`: the floats of a record, its triangle first (more carry what the triangle brings along).
  TriangleBuckets(uint32_t per_axis, uint32_t cube, uint64_t budget, uint32_t record_floats = 9);
  // Host bytes of the per-cube table alone (allocated up front, before any triangle).
  static uint64_t table_bytes(uint32_t per_axis) {
    return uint64_t{per_axis} * per_axis * per_axis * (sizeof(std::vector<float>) + sizeof(std::vector<Chunk>));
  }
  TriangleBuckets(const TriangleBuckets&) = delete;
  TriangleBuckets& operator=(const TriangleBuckets&) = delete;

  void add(const std::vector<float>& grid_triangles);
  // Appends records to cube (x, y, z)'s bucket alone (triangles another rank bucketed there); its estimate stays.
  void put(uint32_t x, uint32_t y, uint32_t z, const std::vector<float>& records);
  // The triangles of cube (x, y, z) (in cubes), in no particular order; the bucket is emptied.
  std::vector<float> take(uint32_t x, uint32_t y, uint32_t z);
  uint64_t spilled_bytes() const { return file_bytes_; }
  // About how many voxels the triangles put in cube (x, y, z)'s bucket will make there: each triangle's area
  // projected on its dominant axis, plus one, shared evenly among the buckets its box meets.
  double voxel_estimate(uint32_t x, uint32_t y, uint32_t z) const { return estimate_[bucket(x, y, z)]; }

 private:
  struct Chunk {
    uint64_t offset, floats;
  };
  void spill();
  size_t bucket(uint32_t x, uint32_t y, uint32_t z) const { return (size_t{z} * per_axis_ + y) * per_axis_ + x; }

  uint32_t per_axis_, cube_, record_;
  uint64_t budget_, held_ = 0;            // bytes of triangles in memory
  std::vector<std::vector<float>> mem_;   // per bucket, not yet spilled
  std::vector<std::vector<Chunk>> chunks_;  // per bucket, its chunks in the spill file
  std::vector<double> estimate_;            // per bucket, voxel_estimate()
  std::unique_ptr<io::TempFile> spill_;
  uint64_t file_bytes_ = 0;
};

}  // namespace mv
