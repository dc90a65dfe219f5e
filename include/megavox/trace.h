// megavox — ray queries against an encoded voxel DAG (svo, svdag, ussvdag or ssvdag), run on a device.
//
// Rays are in the model's own units (the .mvx world-to-grid transform). A hit is the first voxel the ray
// enters: origin + t * direction, t in units of the direction's length (pass unit directions to get
// distances). Cells are half-open like the voxelizer's ([i, i+1)); when a ray crosses several boundaries at
// the same t, the x crossing comes first, then y, then z. Results are the same bytes on every device and
// equal those of a plain voxel-by-voxel DDA (host/ref/trace_reference.h), which the tests check.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "megavox/device.h"
#include "megavox/mvx.h"
#include "megavox/ray.h"

namespace mv {

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
