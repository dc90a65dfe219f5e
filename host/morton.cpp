#include "../kernels/common/morton.h"

#include "megavox/error.h"
#include "megavox/primitives.h"

namespace mv {

void morton_encode(Device& dev, const Buffer& xyz, Buffer& keys, uint32_t n, KeyBits bits) {
  if (n == 0) return;
  uint64_t key_bytes = bits == KeyBits::k64 ? 8 : 4;
  if (xyz.bytes() < uint64_t{n} * 12 || keys.bytes() < uint64_t{n} * key_bytes)
    throw Error("morton_encode: buffers too small for " + std::to_string(n) + " points");
  MvMortonParams p{n, 0};
  const uint32_t local = 64;
  Kernel& k = dev.kernel(bits == KeyBits::k64 ? KernelId::morton_encode64 : KernelId::morton_encode32);
  dev.dispatch(k, dev.groups_for(n, local), local, {&xyz, &keys}, p);
}

}  // namespace mv
