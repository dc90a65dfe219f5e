// megavox.Device: one compute device (an MvDevice) and its configuration.
#pragma once
#include "binding.h"

namespace megavox_py {

class Device {
 public:
  explicit Device(MvDevice d) : d_(d) {}
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;
  ~Device() {
    py::gil_scoped_release release;
    mvReleaseDevice(d_);
  }
  MvDevice get() const { return d_; }

 private:
  MvDevice d_;
};

}  // namespace megavox_py
