// --profile's report and the profile objects of `bench points` and `bench mask`.
#include "profile_report.h"

#include <cstdio>

namespace mv::cli {

namespace {
double narrow_share(const Parallelism& p) { return p.device_seconds > 0 ? p.narrow_seconds / p.device_seconds : 0; }
}  // namespace

nlohmann::json parallelism_json(const Parallelism& p) {
  nlohmann::json kernels = nlohmann::json::array();
  for (const KernelLoad& k : p.kernels)
    kernels.push_back({{"kernel", k.kernel},
                       {"launches", k.launches},
                       {"work_items", k.work_items},
                       {"seconds", k.seconds},
                       {"narrow_seconds", k.narrow_seconds}});
  return {{"wall_seconds", p.wall_seconds},     {"device_seconds", p.device_seconds},
          {"host_seconds", p.host_seconds},     {"wait_seconds", p.wait_seconds},
          {"io_seconds", p.io_seconds},         {"narrow_seconds", p.narrow_seconds},
          {"narrow_share", narrow_share(p)},    {"width", p.width},
          {"kernels", kernels}};
}

void print_parallelism(const std::string& stage, const Parallelism& p) {
  std::fprintf(stderr,
               "profile %s: wall %.4f s = host %.4f + waiting on the device %.4f + file I/O %.4f; device %.4f s, "
               "of it %.4f s (%.1f %%) in dispatches under %llu work-items\n",
               stage.c_str(), p.wall_seconds, p.host_seconds, p.wait_seconds, p.io_seconds, p.device_seconds,
               p.narrow_seconds, 100 * narrow_share(p), (unsigned long long)p.width);
  for (const KernelLoad& k : p.kernels)
    std::fprintf(stderr, "  kernel %-32s %10.4f s %8llu launches %14llu work-items %10.4f s narrow\n",
                 k.kernel.c_str(), k.seconds, (unsigned long long)k.launches, (unsigned long long)k.work_items,
                 k.narrow_seconds);
}

}  // namespace mv::cli
