// megavox — a stage's parallelism profile: how much of its time the device computed, how much the host worked
// on its own, and how much device time went to dispatches too small to fill the device (the serial kernels a
// GPU would stall on). `--profile` prints it; `bench points` and `bench mask` always report it.
#pragma once
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/device.h"

namespace mv {

struct KernelLoad {
  std::string kernel;
  uint64_t launches = 0, work_items = 0;  // work_items: summed over the launches
  double seconds = 0;                     // device time, from timestamps
  double narrow_seconds = 0;              // of launches narrower than the device
};

struct Parallelism {
  double wall_seconds = 0;    // the stage, start to end
  double device_seconds = 0;  // its kernels' execution times, summed (device timestamps)
  double wait_seconds = 0;    // the host blocked on the device (Device::host_wait_ns)
  double io_seconds = 0;      // reading and writing files, reported apart
  double host_seconds = 0;    // wall - wait - io (not below 0): the host's own work
  double narrow_seconds = 0;  // device time of dispatches with fewer work-items than `width`
  uint64_t width = 0;         // work-items the device runs at once (parallel_width)
  std::vector<KernelLoad> kernels;  // most device time first
};

// Work-items `info` runs at once: compute_units x preferred_work_group_size x 4 (a few groups in flight per
// unit to hide latency). compute_units 0 (not reported) counts as 1.
uint64_t parallel_width(const DeviceInfo& info);

// The profile of a stage from its dispatches' timings, its wall time, the host's waits and its file I/O.
Parallelism parallelism_profile(const std::vector<KernelTiming>& timings, uint64_t width, double wall_seconds,
                                double wait_seconds, double io_seconds);

// Sums profiles of parts of one stage (repeated calls); the width of the first.
void accumulate(Parallelism& total, const Parallelism& part);

// Measures stages on a Device opened with profile = true: start() drops the timings of earlier work and notes
// the clock and Device::host_wait_ns; stop() finishes the device (its timings are collected then) and returns the
// profile of what ran between. A meter may run several times; each stop() is one stage.
class ParallelismMeter {
 public:
  explicit ParallelismMeter(Device& dev) : dev_(dev) {}
  void start();
  Parallelism stop(double io_seconds = 0);

 private:
  Device& dev_;
  std::chrono::steady_clock::time_point start_{};
  uint64_t wait_ns_ = 0;
};

}  // namespace mv
