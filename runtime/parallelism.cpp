// The parallelism profile: plain arithmetic over a stage's dispatch timings (megavox/parallelism.h).
#include "megavox/parallelism.h"

#include <algorithm>
#include <map>

namespace mv {

uint64_t parallel_width(const DeviceInfo& info) {
  return uint64_t{std::max<uint32_t>(info.compute_units, 1)} * std::max<uint32_t>(info.preferred_work_group_size, 1) * 4;
}

Parallelism parallelism_profile(const std::vector<KernelTiming>& timings, uint64_t width, double wall_seconds,
                                double wait_seconds, double io_seconds) {
  Parallelism p;
  p.wall_seconds = wall_seconds;
  p.wait_seconds = wait_seconds;
  p.io_seconds = io_seconds;
  p.host_seconds = std::max(0.0, wall_seconds - wait_seconds - io_seconds);
  p.width = width;
  std::map<std::string, KernelLoad> by_name;
  for (const KernelTiming& t : timings) {
    const double seconds = double(t.ns) * 1e-9;
    KernelLoad& k = by_name[t.kernel];
    k.kernel = t.kernel;
    k.launches += 1;
    k.work_items += t.work_items;
    k.seconds += seconds;
    p.device_seconds += seconds;
    if (t.work_items < width) {
      k.narrow_seconds += seconds;
      p.narrow_seconds += seconds;
    }
  }
  for (auto& [name, k] : by_name) p.kernels.push_back(std::move(k));
  std::stable_sort(p.kernels.begin(), p.kernels.end(),
                   [](const KernelLoad& a, const KernelLoad& b) { return a.seconds > b.seconds; });
  return p;
}

void accumulate(Parallelism& total, const Parallelism& part) {
  if (total.width == 0) total.width = part.width;
  total.wall_seconds += part.wall_seconds;
  total.device_seconds += part.device_seconds;
  total.wait_seconds += part.wait_seconds;
  total.io_seconds += part.io_seconds;
  total.host_seconds += part.host_seconds;
  total.narrow_seconds += part.narrow_seconds;
  for (const KernelLoad& k : part.kernels) {
    auto it = std::find_if(total.kernels.begin(), total.kernels.end(),
                           [&](const KernelLoad& t) { return t.kernel == k.kernel; });
    if (it == total.kernels.end()) {
      total.kernels.push_back(k);
      continue;
    }
    it->launches += k.launches;
    it->work_items += k.work_items;
    it->seconds += k.seconds;
    it->narrow_seconds += k.narrow_seconds;
  }
  std::stable_sort(total.kernels.begin(), total.kernels.end(),
                   [](const KernelLoad& a, const KernelLoad& b) { return a.seconds > b.seconds; });
}

void ParallelismMeter::start() {
  dev_.finish();
  dev_.take_timings();
  wait_ns_ = dev_.host_wait_ns();
  start_ = std::chrono::steady_clock::now();
}

Parallelism ParallelismMeter::stop(double io_seconds) {
  dev_.finish();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double wait = double(dev_.host_wait_ns() - wait_ns_) * 1e-9;
  return parallelism_profile(dev_.take_timings(), parallel_width(dev_.info()), wall, wait, io_seconds);
}

}  // namespace mv
