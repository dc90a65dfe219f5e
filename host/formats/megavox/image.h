// megavox — an 8-bit RGB picture (what a render makes) and its writers: plain data, no device types.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace mv {

struct Image {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgb;  // rows top to bottom, 3 bytes per pixel
};

// Writes an 8-bit RGB PNG (to a temporary name, renamed on success). Throws mv::Error on I/O failure.
void write_png(const std::string& path, const Image& image);
// The image as the name's extension says: JPEG (libjpeg-turbo, quality 92) for .jpg / .jpeg, else PNG.
void write_image(const std::string& path, const Image& image);

}  // namespace mv
