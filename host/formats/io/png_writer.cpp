// PNG output through libpng, written to a temporary name and renamed on success.
#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <string>

#include "atomic_file.h"
#include "file_ops.h"
#include "megavox/error.h"
#include "megavox/image.h"
#include "png_grey.h"

namespace mv {

namespace {

// libpng's output goes through io::write_all (the file layer tests inject faults into); a failed write
// ends the encode through png_error, keeping errno for the message.
struct PngOut {
  std::FILE* f;
  int err = 0;
};

void png_write_chunk(png_structp png, png_bytep data, png_size_t bytes) {
  auto* out = static_cast<PngOut*>(png_get_io_ptr(png));
  if (!io::write_all(out->f, data, bytes)) {
    out->err = errno ? errno : EIO;
    png_error(png, "write failed");
  }
}

void png_flush_chunk(png_structp) {}  // write_atomically flushes once at the end

// libpng's errors end the encode by longjmp, silently: write_png throws with the reason instead.
void png_fail(png_structp png, png_const_charp) { png_longjmp(png, 1); }
void png_warn(png_structp, png_const_charp) {}

// libpng reports errors by longjmp; this wraps the whole encode so no C++ object lives across the jump (`out`
// lives in the caller: what the write callback sets survives the jump).
bool encode_png(PngOut& out, uint32_t width, uint32_t height, int channels, const uint8_t* pixels, std::string& why) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, &png_fail, &png_warn);
  if (!png) {
    why = "out of memory";
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    why = out.err ? std::strerror(out.err) : "libpng failed while writing";
    errno = out.err;
    return false;
  }
  png_set_write_fn(png, &out, &png_write_chunk, &png_flush_chunk);
  png_set_IHDR(png, info, width, height, 8, channels == 3 ? PNG_COLOR_TYPE_RGB : PNG_COLOR_TYPE_GRAY,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (uint32_t y = 0; y < height; ++y) png_write_row(png, const_cast<png_bytep>(pixels + size_t{y} * width * channels));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

void write_png(const std::string& path, const Image& image) {
  if (image.width == 0 || image.height == 0 || image.rgb.size() != size_t{image.width} * image.height * 3)
    throw Error("write_png: the image is empty or its size does not match its pixels");
  std::string why;
  try {
    io::write_atomically(path, [&](std::FILE* f) {
      PngOut out{f};
      return encode_png(out, image.width, image.height, 3, image.rgb.data(), why);
    });
  } catch (const Error& e) {
    if (why.empty()) throw;
    throw IoError("cannot write '" + path + "': " + why);
  }
}

namespace io {

void write_png_grey(const std::string& path, uint32_t width, uint32_t height, const std::vector<uint8_t>& grey) {
  if (width == 0 || height == 0 || grey.size() != size_t{width} * height)
    throw Error("write_png_grey: the image is empty or its size does not match its pixels");
  std::string why;
  try {
    write_atomically(path, [&](std::FILE* f) {
      PngOut out{f};
      return encode_png(out, width, height, 1, grey.data(), why);
    });
  } catch (const Error& e) {
    if (why.empty()) throw;
    throw IoError("cannot write '" + path + "': " + why);
  }
}

}  // namespace io

}  // namespace mv
