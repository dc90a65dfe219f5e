// A JPEG of raw pixels through libjpeg-turbo, in memory: test images for the image reader's tests and the fuzz
// seeds (fuzz/mask_seeds.h), one encoder for both.
#pragma once
#include <cstdio>  // before jpeglib.h, which uses FILE and size_t
#include <cstdlib>

#include <jpeglib.h>

#include <cstdint>
#include <vector>

namespace mv::test {

// `px` holds w x h pixels of `channels` (1: grey, 3: RGB) bytes each.
inline std::vector<uint8_t> encode_jpeg(uint32_t w, uint32_t h, int channels, const std::vector<uint8_t>& px,
                                        int quality = 100) {
  jpeg_compress_struct c;
  jpeg_error_mgr err;
  c.err = jpeg_std_error(&err);
  jpeg_create_compress(&c);
  unsigned char* out = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&c, &out, &size);
  c.image_width = w;
  c.image_height = h;
  c.input_components = channels;
  c.in_color_space = channels == 3 ? JCS_RGB : JCS_GRAYSCALE;
  jpeg_set_defaults(&c);
  jpeg_set_quality(&c, quality, TRUE);
  jpeg_start_compress(&c, TRUE);
  while (c.next_scanline < h) {
    JSAMPROW row = const_cast<JSAMPLE*>(&px[size_t{c.next_scanline} * w * channels]);
    jpeg_write_scanlines(&c, &row, 1);
  }
  jpeg_finish_compress(&c);
  std::vector<uint8_t> bytes(out, out + size);
  jpeg_destroy_compress(&c);
  std::free(out);
  return bytes;
}

}  // namespace mv::test
