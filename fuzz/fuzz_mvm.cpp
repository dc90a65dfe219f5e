// decode_mvm (host/formats/io/mvm_file.h): mask models, every field, the size and the checksum checked. Each input is
// read twice, as it is and with its XXH64 recomputed, so mutations get past the checksum to the fields.
#include <xxhash.h>

#include <cstring>
#include <vector>

#include "fuzz_support.h"
#include "io/mvm_file.h"
#include "megavox/error.h"

namespace {

void read(const std::vector<uint8_t>& bytes) {
  try {
    const mv::MaskModel m = mv::io::decode_mvm(bytes, "input");
    MV_FUZZ_CHECK(m.channels == 1 || m.channels == 3);
    MV_FUZZ_CHECK(m.fg.size() == m.bins() && m.bg.size() == m.bins());
  } catch (const mv::Error&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<uint8_t> bytes(data, data + size);
  read(bytes);
  if (size >= 16) {
    const uint64_t sum = XXH64(bytes.data(), size - 8, 0);
    std::memcpy(bytes.data() + size - 8, &sum, 8);
    read(bytes);
  }
  return 0;
}
