// Device discovery across both backends and the --device / MEGAVOX_DEVICE selector.
#include <algorithm>
#include <cctype>
#include <cstdlib>

#include "backend.h"
#include "megavox/device.h"
#include "megavox/error.h"

namespace mv {

std::vector<DeviceInfo> list_devices() {
  std::vector<DeviceInfo> all = rt::enumerate_opencl();
  for (auto& d : rt::enumerate_vulkan()) all.push_back(std::move(d));
  return all;
}

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::string device_list(const std::vector<DeviceInfo>& all) {
  if (all.empty()) return "  (none: install an OpenCL ICD such as pocl-opencl-icd, or a Vulkan driver such as mesa-vulkan-drivers)";
  std::string s;
  for (const auto& d : all) s += "  " + d.selector() + "  " + d.name + "  [" + d.platform + ", " + d.type + "]\n";
  s.pop_back();
  return s;
}

// "ocl:3" -> ("opencl", 3); returns false when `sel` is not of that form.
bool parse_indexed(const std::string& sel, std::string& backend, int& index) {
  for (auto [prefix, name] : {std::pair{"ocl:", "opencl"}, std::pair{"vk:", "vulkan"}}) {
    std::string p = prefix;
    if (sel.rfind(p, 0) != 0) continue;
    std::string digits = sel.substr(p.size());
    if (digits.empty() || digits.size() > 6 || !std::all_of(digits.begin(), digits.end(), ::isdigit)) return false;
    backend = name;
    index = std::stoi(digits);
    return true;
  }
  return false;
}

}  // namespace

DeviceInfo select_device(const std::string& selector_in) {
  std::string selector = selector_in;
  if (selector.empty())
    if (const char* env = std::getenv("MEGAVOX_DEVICE")) selector = env;
  std::vector<DeviceInfo> all = list_devices();

  if (selector.empty()) {
    auto first = [&](auto pred) { return std::find_if(all.begin(), all.end(), pred); };
    auto it = first([](const DeviceInfo& d) { return d.type == "gpu" && d.backend == "vulkan"; });
    if (it == all.end()) it = first([](const DeviceInfo& d) { return d.type == "gpu"; });
    if (it == all.end()) it = first([](const DeviceInfo& d) { return d.backend == "opencl" && d.type == "cpu"; });
    if (it == all.end()) it = all.begin();
    if (it == all.end()) throw Error("no compute device found.\nDevices:\n" + device_list(all));
    return *it;
  }

  std::string backend;
  int index = 0;
  if (parse_indexed(selector, backend, index)) {
    for (const auto& d : all)
      if (d.backend == backend && d.index == index) return d;
  } else {
    std::string needle = lower(selector);
    for (const auto& d : all)
      if (lower(d.name + "\n" + d.platform + "\n" + d.vendor).find(needle) != std::string::npos) return d;
  }
  throw Error("no device matches '" + selector + "'. Devices:\n" + device_list(all));
}

}  // namespace mv
