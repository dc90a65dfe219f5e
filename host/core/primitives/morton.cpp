#include "common/morton.h"

#include "primitives/chunking.h"
#include "megavox/error.h"
#include "megavox/primitives.h"

namespace mv {

void morton_encode(Device& dev, const Buffer& xyz, Buffer& keys, uint64_t n, KeyBits bits) {
  if (n == 0) return;
  detail::check_device_items("morton_encode", n);
  uint64_t key_bytes = bits == KeyBits::k64 ? 8 : 4;
  if (xyz.bytes() < n * 12 || keys.bytes() < n * key_bytes)
    throw Error("morton_encode: buffers too small for " + std::to_string(n) + " points");
  MvMortonParams p{static_cast<uint32_t>(n), 0};
  const uint32_t local = 64;
  Kernel& k = dev.kernel(bits == KeyBits::k64 ? KernelId::morton_encode64 : KernelId::morton_encode32);
  dev.dispatch(k, dev.groups_for(n, local), local, {&xyz, &keys}, p);
}

}  // namespace mv
