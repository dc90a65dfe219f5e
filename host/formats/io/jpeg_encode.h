// Raw pixels to JPEG bytes in memory through libjpeg-turbo: megavox's JPEG output (write_image) and the test
// images and fuzz seeds of the image reader, one encoder for all.
#pragma once
#include <csetjmp>
#include <cstdio>  // before jpeglib.h, which uses FILE and size_t
#include <cstdlib>

#include <jpeglib.h>

#include <cstdint>
#include <vector>

namespace mv::io {

// `px` holds w x h pixels of `channels` (1: grey, 3: RGB) bytes each. Empty when libjpeg fails (out of memory).
inline std::vector<uint8_t> encode_jpeg(uint32_t w, uint32_t h, int channels, const std::vector<uint8_t>& px,
                                        int quality = 92) {
  // libjpeg's default error handler exits the process; this one jumps back here instead.
  struct Errors {
    jpeg_error_mgr mgr;
    std::jmp_buf back;
  } err;
  jpeg_compress_struct c;
  c.err = jpeg_std_error(&err.mgr);
  err.mgr.error_exit = [](j_common_ptr info) { std::longjmp(reinterpret_cast<Errors*>(info->err)->back, 1); };
  unsigned char* out = nullptr;
  unsigned long size = 0;
  if (setjmp(err.back)) {
    jpeg_destroy_compress(&c);
    std::free(out);
    return {};
  }
  jpeg_create_compress(&c);
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

}  // namespace mv::io
