// The device side of ray traversal: one encoded DAG uploaded, and dispatches of the trace and
// secondary-ray kernels (kernels/common/trace.h, secondary.h) over rays in root-cube coordinates.
#pragma once
#include <cstdint>

#include "../../kernels/common/secondary.h"
#include "megavox/device.h"
#include "megavox/encode.h"

namespace mv {

class TraceEngine {
 public:
  TraceEngine(Device& dev, const EncodedDag& dag);

  Device& device() { return dev_; }
  uint32_t levels() const { return levels_; }
  // ssvdag: read every level's start from memory (the kernel for trees deeper than the parameters hold) even
  // when the parameters would do; for tests of that kernel on small trees.
  void read_level_offsets_from_memory() { offsets_in_memory_ = true; }
  // A step limit the device can run (lavapipe ends loops at 65535 iterations).
  uint32_t step_limit(uint32_t wanted) const;

  // Traces `count` rays: from `rays` (MV_RAY_FLOATS each) or, with `camera`, the camera's pixel rays. Writes
  // MV_HIT_WORDS per ray into `results`, or with `occlusion` adds 1 to results[i] when ray i hits.
  void trace(const Buffer* rays, const Buffer* camera, uint32_t count, uint32_t width, float proj,
             uint32_t max_steps, bool occlusion, Buffer& results);

  // Writes one secondary ray per primary ray (p.first / p.count are set here).
  void secondary(const Buffer* rays, const Buffer* camera, const Buffer& hits, const Buffer* table, uint32_t count,
                 MvSecondaryParams p, Buffer& out);

 private:
  template <class F>
  void for_each_dispatch(uint32_t count, F&& dispatch);

  Device& dev_;
  uint32_t levels_ = 0;
  uint32_t encoding_ = 0;
  Buffer words_, bricks_, level_offsets_;
  bool offsets_in_memory_ = false;
  MvTraceParams params_{};  // levels and ssvdag level starts
};

}  // namespace mv
