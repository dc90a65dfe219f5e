// `megavox bench cache`: a camera flight over a paged .mvx rendered through the device page cache, against
// the fully resident render of the same file in the same run (today's kernel, the whole DAG on the device).
// Per frame: wall time of both, the cache's share of the paged frame (management: stamp, LRU, request and
// invalidation kernels and the host's waits; reading and uploading pages apart), pages and bytes streamed,
// the hit rate, whether the picture equals the resident one byte for byte, and the address layer's cost on
// the resident path: the view's last pass through a second cache that holds every page it reads (as large as
// one allocation allows; preloaded when it holds every page) against the resident kernel, best of
// kAddressSamples each, in pairs of alternating order.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/device.h"
#include "megavox/render.h"

namespace mv::bench {

inline constexpr int kAddressSamples = 5;

struct FlightFrame {
  double resident_seconds = 0, paged_seconds = 0;  // whole frames (trace, shading, downloads)
  double resident_trace_seconds = 0;               // the resident frame's trace passes
  double last_pass_trace_seconds = 0;              // the paged kernel's trace, every page of the view resident
  double resident_best_trace_seconds = 0;          // the resident kernel's, sampled as last_pass_trace_seconds
  double manage_seconds = 0, produce_seconds = 0;  // the cache's, summed over the frame's passes
  double read_ahead_seconds = 0;                   // pages read ahead on their own thread, while tracing
  uint32_t passes = 0;
  uint64_t pages_loaded = 0, pages_evicted = 0, bytes_uploaded = 0, pages_read_ahead = 0;
  double hit_rate = 0;
  bool converged = false, identical = false;
};

struct FlightBenchResult {
  std::vector<FlightFrame> frames;
  uint32_t slots = 0, pages = 0, page_words = 0;
  uint32_t warm_slots = 0;   // the address measurement's cache (0: it did not fit; no address figure)
  double resident_seconds = 0, paged_seconds = 0, manage_seconds = 0, produce_seconds = 0, read_ahead_seconds = 0;
  uint64_t pages_read_ahead = 0;
  double resident_trace_seconds = 0, last_pass_trace_seconds = 0;
  double manage_share = 0;   // manage_seconds / paged_seconds
  double address_cost = 0;   // last_pass_trace_seconds / resident_trace_seconds
  double hit_rate = 0;
  uint64_t bytes_uploaded = 0;
  uint32_t identical = 0;    // frames byte-identical to the resident render
};

// `frames` cameras orbiting the model's centre at `distance` times the distance that frames it (the iso view's
// height, looking at the centre).
std::vector<Camera> orbit_flight(const Bounds& bounds, uint32_t frames, double distance, double fov);

FlightBenchResult run_flight_bench(Device& dev, const std::string& paged_mvx, const std::vector<Camera>& flight,
                                   const RenderOptions& options, uint64_t cache_bytes);

}  // namespace mv::bench
