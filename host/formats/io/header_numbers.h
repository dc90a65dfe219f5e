// Small helpers the file-header parsers share: counts in messages, and sizes computed from untrusted header
// counts without overflow.
#pragma once
#include <cstdint>
#include <limits>
#include <string>

namespace mv::io::detail {

inline std::string num(uint64_t v) { return std::to_string(v); }

// Saturating arithmetic: a product or sum past 2^64 - 1 stays there, so a comparison with a file size fails.
inline uint64_t sat_mul(uint64_t a, uint64_t b) {
  uint64_t r;
  return __builtin_mul_overflow(a, b, &r) ? std::numeric_limits<uint64_t>::max() : r;
}

inline uint64_t sat_add(uint64_t a, uint64_t b) {
  uint64_t r;
  return __builtin_add_overflow(a, b, &r) ? std::numeric_limits<uint64_t>::max() : r;
}

}  // namespace mv::io::detail
