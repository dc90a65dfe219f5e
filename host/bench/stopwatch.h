// Wall-clock timing shared by the benchmarks.
#pragma once
#include <chrono>

namespace mv::bench {

using Clock = std::chrono::steady_clock;

// Seconds from t0 to now.
inline double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace mv::bench
