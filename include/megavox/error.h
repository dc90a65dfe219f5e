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

// The device memory budget (or the largest single allocation) cannot hold a buffer: a smaller problem
// (smaller out-of-core cubes) may still fit.
class DeviceMemoryError : public Error {
 public:
  using Error::Error;
};

}  // namespace mv
