#include "trace/trace_layout.h"

#include <algorithm>
#include <cstring>

namespace mv {

std::vector<uint32_t> trace_words(const EncodedDag& dag) {
  if (dag.encoding != Encoding::ssvdag) return dag.words;
  std::vector<uint32_t> words(std::max<size_t>((dag.inner.size() + 1) / 2, 1) + 1, 0);  // an empty one too
  if (!dag.inner.empty()) std::memcpy(words.data(), dag.inner.data(), dag.inner.size() * 2);
  return words;
}

std::vector<uint32_t> trace_bricks(const EncodedDag& dag) {
  std::vector<uint32_t> halves(dag.bricks.size() * 2);
  if (!dag.bricks.empty()) std::memcpy(halves.data(), dag.bricks.data(), dag.bricks.size() * 8);
  return halves;
}

std::vector<uint32_t> trace_level_offsets(const EncodedDag& dag) {
  if (dag.encoding != Encoding::ssvdag) return {};
  std::vector<uint32_t> offsets(dag.levels + 1, 0);
  for (uint32_t l = 0; l <= dag.levels && l < dag.level_offset.size(); ++l)
    offsets[l] = static_cast<uint32_t>(dag.level_offset[l]);
  return offsets;
}

void set_trace_levels(MvTraceParams& p, const EncodedDag& dag) {
  p.mode = MV_TRACE_MODE(dag.levels, 0u, 0u, 0u);
  if (dag.encoding != Encoding::ssvdag) return;
  for (uint32_t k = 0; k < MV_TRACE_PARAM_LEVELS && 3 + k < dag.level_offset.size(); ++k)
    p.level_base[k] = static_cast<uint32_t>(dag.level_offset[3 + k]);
}

}  // namespace mv
