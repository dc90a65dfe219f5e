#include "test_support.h"

#include <cctype>
#include <map>
#include <memory>

namespace mv::test {

const std::vector<DeviceInfo>& all_devices() {
  static const std::vector<DeviceInfo> devices = list_devices();
  return devices;
}

Device& shared_device(const DeviceInfo& info) {
  static std::map<std::string, std::unique_ptr<Device>> open;
  auto& slot = open[info.selector()];
  if (!slot) slot = Device::open({info.selector(), 0, false});
  return *slot;
}

std::string device_test_name(const ::testing::TestParamInfo<DeviceInfo>& p) {
  const DeviceInfo& d = p.param;
  std::string lname = d.name + " " + d.platform;
  for (auto& c : lname) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  std::string tag = lname.find("pocl") != std::string::npos || lname.find("portable computing") != std::string::npos
                        ? "pocl"
                    : lname.find("llvmpipe") != std::string::npos ? "llvmpipe"
                                                                  : d.type;
  std::string sel = d.selector();
  for (auto& c : sel)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return tag + "_" + d.backend + "_" + sel;
}

std::vector<uint32_t> random_u32(size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<uint32_t> v(n);
  for (auto& x : v) x = static_cast<uint32_t>(rng());
  return v;
}

std::vector<uint64_t> random_u64(size_t n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<uint64_t> v(n);
  for (auto& x : v) x = rng();
  return v;
}

}  // namespace mv::test
