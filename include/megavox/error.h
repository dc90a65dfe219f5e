// megavox — the one exception type thrown across module boundaries.
#pragma once
#include <stdexcept>
#include <string>

namespace mv {

// Carries a complete, user-facing message ("what went wrong, with what, and what is left").
// The CLI prints what() on one line and exits non-zero.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace mv
