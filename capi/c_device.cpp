// The C API: versions, errors and devices.
#include <sstream>
#include <utility>

#include "handles.h"
#include "megavox/build.h"

namespace mv::capi {

namespace {

// Errors of mvNewDevice and of calls given no device.
struct ThreadError {
  MvError code = MV_ERROR_NONE;
  std::string message;
};
thread_local ThreadError t_error;

struct Config {
  DeviceOptions device;
  uint64_t host_memory = 0;
  uint64_t cache_memory = 0;
};

uint64_t config_size(const std::string& key, const std::string& value) {
  try {
    return parse_size(value);
  } catch (const Error&) {
    throw ApiError(MV_ERROR_INVALID_ARGUMENT, "device config: " + key + "=" + value + " is not a size (examples: 512M, 2G)");
  }
}

// "device=vk:0,memory=512M,host_memory=2G,kernel_shape=gpu"
Config parse_config(const char* text) {
  Config c;
  std::stringstream in(text ? text : "");
  std::string item;
  while (std::getline(in, item, ',')) {
    if (item.find_first_not_of(' ') == std::string::npos) continue;
    const size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw ApiError(MV_ERROR_INVALID_ARGUMENT,
                     "device config: '" + item + "' is not key=value (keys: device, memory, host_memory, cache_memory, kernel_shape)");
    std::string key = item.substr(0, eq), value = item.substr(eq + 1);
    key.erase(0, key.find_first_not_of(' '));
    key.erase(key.find_last_not_of(' ') + 1);
    if (key == "device") {
      c.device.selector = value;
    } else if (key == "memory") {
      c.device.memory_budget = config_size(key, value);
    } else if (key == "host_memory") {
      c.host_memory = config_size(key, value);
    } else if (key == "cache_memory") {
      c.cache_memory = config_size(key, value);
      if (c.cache_memory == 0) throw ApiError(MV_ERROR_INVALID_ARGUMENT, "device config: cache_memory=0 holds no page");
    } else if (key == "kernel_shape") {
      if (value != "auto" && value != "gpu" && value != "cpu")
        throw ApiError(MV_ERROR_INVALID_ARGUMENT, "device config: kernel_shape=" + value + " is none of auto, gpu, cpu");
      c.device.kernel_shape = parse_kernel_shape(value);
    } else {
      throw ApiError(MV_ERROR_INVALID_ARGUMENT, "device config: unknown key '" + key +
                                                    "' (keys: device, memory, host_memory, cache_memory, kernel_shape)");
    }
  }
  return c;
}

}  // namespace

void record_error(MvDevice device, MvError code, const std::string& message) {
  if (!device) {
    t_error = {code, message};
    return;
  }
  MvErrorFunction f;
  void* user;
  std::string copy;
  {
    std::lock_guard<std::mutex> g(device->error_lock);
    device->error = code;
    device->message = message;
    f = device->error_function;
    user = device->error_user;
    copy = message;
  }
  if (f) f(user, code, copy.c_str());
}

}  // namespace mv::capi

using namespace mv::capi;

extern "C" {

uint32_t mvGetVersion(void) { return MV_VERSION_MAJOR * 10000 + MV_VERSION_MINOR * 100 + MV_VERSION_PATCH; }

const char* mvGetVersionString(void) { return MV_VERSION_STRING; }

// mv::ErrorCode (megavox/error.h) is the table every front end shares; the C codes are its values.
static_assert(int(mv::ErrorCode::none) == MV_ERROR_NONE && int(mv::ErrorCode::unknown) == MV_ERROR_UNKNOWN &&
              int(mv::ErrorCode::invalid_argument) == MV_ERROR_INVALID_ARGUMENT &&
              int(mv::ErrorCode::invalid_operation) == MV_ERROR_INVALID_OPERATION &&
              int(mv::ErrorCode::out_of_memory) == MV_ERROR_OUT_OF_MEMORY &&
              int(mv::ErrorCode::unsupported_device) == MV_ERROR_UNSUPPORTED_DEVICE &&
              int(mv::ErrorCode::cancelled) == MV_ERROR_CANCELLED && int(mv::ErrorCode::input) == MV_ERROR_INPUT &&
              int(mv::ErrorCode::io) == MV_ERROR_IO && int(mv::ErrorCode::device) == MV_ERROR_DEVICE);

const char* mvGetErrorString(MvError code) { return mv::error_code_name(static_cast<mv::ErrorCode>(code)); }

MvDevice mvNewDevice(const char* config) {
  MvDevice made = nullptr;
  guard(nullptr, [&] {
    const Config c = parse_config(config);
    auto d = std::make_unique<MvDeviceTy>();
    try {
      d->device = mv::Device::open(c.device);
    } catch (const mv::DeviceMemoryError&) {
      throw;
    } catch (const mv::DeviceError&) {
      throw;
    } catch (const mv::CodedError&) {
      throw;
    } catch (const mv::Error& e) {  // no device matches the selector
      throw ApiError(MV_ERROR_UNSUPPORTED_DEVICE, e.what());
    }
    d->host_memory = c.host_memory;
    d->cache_memory = c.cache_memory;
    made = d.release();
  });
  return made;
}

void mvRetainDevice(MvDevice device) { retain(device); }

void mvReleaseDevice(MvDevice device) { release(device); }

MvError mvGetDeviceError(MvDevice device) {
  if (!device) return std::exchange(t_error.code, MV_ERROR_NONE);
  std::lock_guard<std::mutex> g(device->error_lock);
  return std::exchange(device->error, MV_ERROR_NONE);
}

const char* mvGetDeviceLastErrorMessage(MvDevice device) {
  if (!device) return t_error.message.c_str();
  std::lock_guard<std::mutex> g(device->error_lock);
  return device->message.c_str();
}

void mvSetDeviceErrorFunction(MvDevice device, MvErrorFunction function, void* userPtr) {
  if (!device) return record_error(nullptr, MV_ERROR_INVALID_ARGUMENT, "mvSetDeviceErrorFunction: no device");
  std::lock_guard<std::mutex> g(device->error_lock);
  device->error_function = function;
  device->error_user = userPtr;
}

size_t mvListDevices(MvDeviceDescription* devices, size_t capacity) {
  size_t count = 0;
  guard(nullptr, [&] {
    require(devices || capacity == 0, "mvListDevices: devices is NULL");
    const std::vector<mv::DeviceInfo> all = mv::list_devices();
    std::string chosen;
    try {
      chosen = mv::select_device("").selector();
    } catch (const mv::Error&) {  // no device at all, or $MEGAVOX_DEVICE matches none: no default to mark
    }
    for (size_t i = 0; i < all.size() && i < capacity; ++i) {
      const mv::DeviceInfo& d = all[i];
      MvDeviceDescription& out = devices[i];
      out = MvDeviceDescription{};
      copy_text(out.selector, d.selector());
      copy_text(out.name, d.name);
      copy_text(out.backend, d.backend);
      copy_text(out.type, d.type);
      copy_text(out.platform, d.platform);
      out.memoryBytes = d.global_memory_bytes;
      out.isDefault = d.selector() == chosen;
    }
    count = all.size();
  });
  return count;
}

uint64_t mvGetHostMemoryBudget(MvDevice device) {
  return device && device->host_memory ? device->host_memory : mv::default_host_memory();
}

MvError mvGetDeviceInfo(MvDevice device, MvDeviceInfo* info) {
  return guard(device, [&] {
    require(device, "mvGetDeviceInfo: no device");
    require(info, "mvGetDeviceInfo: info is NULL");
    std::lock_guard<std::recursive_mutex> g(device->lock);
    const mv::DeviceInfo& d = device->device->info();
    copy_text(info->name, d.name);
    copy_text(info->backend, d.backend);
    copy_text(info->selector, d.selector());
    info->memoryBudget = device->device->memory_budget();
    info->memoryUsed = device->device->memory_used();
  });
}

}  // extern "C"
