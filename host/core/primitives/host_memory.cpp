// Whether a device computes in host memory (megavox/primitives.h): it maps a buffer into the host's view.
#include "megavox/primitives.h"

namespace mv {

bool computes_in_host_memory(Device& dev) {
  const Buffer probe = dev.alloc(4, "host memory probe");
  return dev.host_view(probe) != nullptr;
}

}  // namespace mv
