// Wall-clock timing shared by the benchmarks.
#pragma once
#include "timing.h"

namespace mv::bench {

using Clock = std::chrono::steady_clock;

// Seconds from t0 to now.
inline double since(Clock::time_point t0) { return seconds_since(t0); }

}  // namespace mv::bench
