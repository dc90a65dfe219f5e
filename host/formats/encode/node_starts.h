// Which words of a 32-bit word stream start a node, as a bitmap with a count per 64 words, so that "is this a
// node start?" and "which node is it?" (its index among all starts, in stream order) each take O(1): the
// checks and parses of a whole stream (validate_svdag, page_layout) look up every pointer this way instead
// of a binary search per pointer. 1/8 + 1/2 byte a word.
#pragma once
#include <cstdint>
#include <vector>

namespace mv {

class NodeStarts {
 public:
  explicit NodeStarts(uint64_t words) : bits_((words + 63) / 64, 0) {}
  void set(uint64_t w) { bits_[w >> 6] |= uint64_t{1} << (w & 63); }
  bool test(uint64_t w) const { return w >> 6 < bits_.size() && (bits_[w >> 6] >> (w & 63) & 1); }
  // After the last set(): the counts behind index().
  void count() {
    before_.resize(bits_.size());
    uint32_t n = 0;
    for (size_t i = 0; i < bits_.size(); ++i) {
      before_[i] = n;
      n += static_cast<uint32_t>(__builtin_popcountll(bits_[i]));
    }
  }
  // The index of the start at word w (test(w) must hold; count() must have run).
  uint32_t index(uint64_t w) const {
    const uint64_t below = bits_[w >> 6] & ((uint64_t{1} << (w & 63)) - 1);
    return before_[w >> 6] + static_cast<uint32_t>(__builtin_popcountll(below));
  }

 private:
  std::vector<uint64_t> bits_;
  std::vector<uint32_t> before_;  // starts in the blocks before block i
};

}  // namespace mv
