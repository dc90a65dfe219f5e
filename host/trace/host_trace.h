// The traversal kernel's own code (kernels/common/trace.h) compiled for the host, over an encoded DAG in
// host memory: the CPU build of the kernel, for heat-map references and as a benchmark baseline.
#pragma once
#include <cstdint>
#include <cstring>
#include <vector>

#include "../../kernels/common/trace.h"
#include "megavox/encode.h"

namespace mv {

class HostTracer {
 public:
  explicit HostTracer(const EncodedDag& dag) : enc_(uint32_t(dag.encoding)), levels_(dag.levels) {
    if (dag.encoding == Encoding::ssvdag) {
      std::vector<uint16_t> inner = dag.inner;
      if (inner.size() % 2) inner.push_back(0);
      words_.resize(inner.size() / 2);
      std::memcpy(words_.data(), inner.data(), inner.size() * 2);
      bricks_.resize(dag.bricks.size() * 2);
      std::memcpy(bricks_.data(), dag.bricks.data(), dag.bricks.size() * 8);
      for (uint64_t o : dag.level_offset) offsets_.push_back(uint32_t(o));
    } else {
      words_ = dag.words;
    }
  }
  MvHit trace(const MvRay& r, float proj, uint32_t max_steps) {
    return mv_trace(words_.data(), bricks_.data(), offsets_.data(), enc_, levels_, r, proj, max_steps);
  }

 private:
  uint32_t enc_, levels_;
  std::vector<uint32_t> words_, bricks_, offsets_;
};

}  // namespace mv
