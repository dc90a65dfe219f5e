// Wall-clock timing for the stage times that reports and benchmarks print.
#pragma once
#include <chrono>

namespace mv {

// Seconds from t0 to now on the steady clock.
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace mv
