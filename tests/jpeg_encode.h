// JPEG test images for the image reader's tests and the fuzz seeds (fuzz/mask_seeds.h): the library's own
// encoder, at full quality unless asked.
#pragma once
#include "io/jpeg_encode.h"

namespace mv::test {

inline std::vector<uint8_t> encode_jpeg(uint32_t w, uint32_t h, int channels, const std::vector<uint8_t>& px,
                                        int quality = 100) {
  return io::encode_jpeg(w, h, channels, px, quality);
}

}  // namespace mv::test
