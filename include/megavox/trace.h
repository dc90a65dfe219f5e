// megavox — ray queries against an encoded voxel DAG (svo, svdag, ussvdag or ssvdag), run on a device.
//
// Rays are in the model's own units (the .mvx world-to-grid transform). A hit is the first voxel the ray
// enters: origin + t * direction, t in units of the direction's length (pass unit directions to get
// distances). Cells are half-open like the voxelizer's ([i, i+1)); when a ray crosses several boundaries at
// the same t, the x crossing comes first, then y, then z. Results are the same bytes on every device and
// equal those of a plain voxel-by-voxel DDA (host/ref/trace_reference.h), which the tests check.
#pragma once
#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "megavox/device.h"
#include "megavox/mvx.h"

namespace mv {

struct Ray {
  float origin[3] = {0, 0, 0};
  float direction[3] = {0, 0, 1};  // need not be unit; components of magnitude below 1e-20 count as 1e-20
  float tmax = std::numeric_limits<float>::infinity();
};

struct RayHit {
  bool hit = false;
  bool gave_up = false;       // stopped after TraceOptions::max_steps without an answer
  float t = 0;                // the hit point is origin + t * direction
  uint32_t level = 0;         // 0: a voxel; above 0 a coarser cell (level-of-detail queries)
  int normal[3] = {0, 0, 0};  // the face entered (axis-aligned); zero when the ray starts in a full voxel
  uint32_t cell[3] = {0, 0, 0};  // the cell at `level`; its first voxel is cell << level
  uint32_t steps = 0;            // traversal steps taken (a cost measure)
};

struct TraceOptions {
  // Traversal steps after which a ray gives up (the same limit on every device; lavapipe caps shader
  // loops at 65535 iterations).
  uint32_t max_steps = 60000;
};

class TraceEngine;

// Uploads one encoded DAG to a device and answers batches of rays with the same kernel the renderer uses.
class Tracer {
 public:
  Tracer(Device& dev, const MvxFile& file);
  ~Tracer();
  Tracer(const Tracer&) = delete;
  Tracer& operator=(const Tracer&) = delete;

  std::vector<RayHit> trace(const std::vector<Ray>& rays, const TraceOptions& options = {});

  TraceEngine& engine() { return *engine_; }
  const GridTransform& grid() const { return grid_; }

 private:
  GridTransform grid_;
  std::unique_ptr<TraceEngine> engine_;
};

}  // namespace mv
