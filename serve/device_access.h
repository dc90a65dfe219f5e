// The library's own device behind a worker's C API handle. Point-cloud and mask jobs call the C++ API (the C
// API has no entry points for them) on the worker's context, so they share its budget rather than open a
// second context; they hold the handle's lock as every C API entry point does.
#pragma once
#include <mutex>

#include "handles.h"

namespace mv::serve {

// Calls f(mv::Device&, host_memory) with the device locked; host_memory is the worker's RAM budget (0: the default).
template <class F>
void on_device(MvDevice dev, F&& f) {
  std::lock_guard<std::recursive_mutex> g(dev->lock);
  f(*dev->device, dev->host_memory);
}

}  // namespace mv::serve
