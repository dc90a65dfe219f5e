// .mvm files: a mask model (include/megavox/mask_model.h), versioned and checksummed.
//   0  8 bytes  "MVMASK\r\n" (a text-mode copy breaks the CR LF)
//   8  u32      version (1)
//  12  u32      channels: 1 or 3
//  16  u32      bins: 32 (1 channel) or 1024 (3 channels)
//  20  u32      0
//  24  u64[bins] foreground training pixels per bin, then u64[bins] background ones
//  end u64      XXH64 (seed 0) of every byte before it
// Little-endian. The reader checks every field, the exact size and the checksum before returning.
#pragma once
#include <cstdint>
#include <span>
#include <string>

#include "megavox/mask_model.h"

namespace mv::io {

inline constexpr uint32_t kMvmVersion = 1;

void write_mvm(const std::string& path, const MaskModel& model);  // to a temporary name, then renamed
MaskModel decode_mvm(std::span<const uint8_t> bytes, const std::string& name);
MaskModel read_mvm(const std::string& path);

}  // namespace mv::io
