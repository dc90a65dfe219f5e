// PNG output through libpng, written to a temporary name and renamed on success.
#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <string>

#include "atomic_file.h"
#include "megavox/error.h"
#include "megavox/render.h"

namespace mv {

namespace {

// libpng reports errors by longjmp; this wraps the whole encode so no C++ object lives across the jump.
bool encode_png(std::FILE* f, const Image& image, std::string& why) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  if (!png) {
    why = "out of memory";
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    why = "libpng failed while writing";
    return false;
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (uint32_t y = 0; y < image.height; ++y)
    png_write_row(png, const_cast<png_bytep>(&image.rgb[size_t{y} * image.width * 3]));
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
    io::write_atomically(path, [&](std::FILE* f) { return encode_png(f, image, why); });
  } catch (const Error& e) {
    throw Error(why.empty() ? e.what() : "cannot write '" + path + "': " + why);
  }
}

}  // namespace mv
