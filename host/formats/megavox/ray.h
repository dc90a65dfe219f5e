// megavox — ray queries as plain data: a ray, what it hit, and how far a query may walk (no device types).
#pragma once
#include <cstdint>
#include <limits>

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
  bool coarse = false;           // paged: stopped at this cell because the page below it was not loaded
};

struct TraceOptions {
  // Traversal steps after which a ray gives up (the same limit on every device; lavapipe caps shader
  // loops at 65535 iterations).
  uint32_t max_steps = 60000;
  // Paged tracers: passes at most, each loading the pages the previous one missed (RayHit::coarse marks
  // rays that still stopped at a missing page); 0 = until none is missed.
  uint32_t max_passes = 0;
};

}  // namespace mv
