// The traversal kernel's own code (kernels/common/trace.h) compiled for the host, over an encoded DAG in
// host memory: the CPU build of the kernel, for heat-map references and as a benchmark baseline.
#pragma once
#include <cstdint>
#include <vector>

#include "common/trace.h"
#include "megavox/encode.h"
#include "trace_layout.h"

namespace mv {

class HostTracer {
 public:
  explicit HostTracer(const EncodedDag& dag)
      : enc_(dag.encoding == Encoding::ssvdag ? MV_ENC_SSVDAG : MV_ENC_SVDAG),
        words_(trace_words(dag)),
        bricks_(trace_bricks(dag)),
        offsets_(trace_level_offsets(dag)) {
    set_trace_levels(params_, dag);
  }
  // From t = `start` where > 0 (mv_restart: no event at t <= start may be a hit).
  MvHit trace(const MvRay& r, float proj, uint32_t max_steps, float start = 0) {
    MvTraceParams p = params_;
    p.proj = proj;
    p.max_steps = max_steps;
    return mv_trace(words_.data(), bricks_.data(), offsets_.data(), nullptr, nullptr, enc_, 0u, r, start,
                    p);  // level starts from memory
  }

 private:
  uint32_t enc_;
  std::vector<uint32_t> words_, bricks_, offsets_;
  MvTraceParams params_{};
};

}  // namespace mv
