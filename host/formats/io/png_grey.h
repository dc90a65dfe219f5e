// One-channel 8-bit PNG output (masks), beside write_png's RGB (megavox/image.h); temporary name, then renamed.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace mv::io {

void write_png_grey(const std::string& path, uint32_t width, uint32_t height, const std::vector<uint8_t>& grey);

}  // namespace mv::io
