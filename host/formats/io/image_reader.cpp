// Image decoding through Debian's libraries (libpng, libjpeg-turbo) and a small binary-PNM parser. Both C
// libraries report errors by longjmp: each decode runs in a function that keeps no C++ object with a
// destructor across the jump, and turns the library's message into an mv::Error afterwards.
#include "image_reader.h"

#include <cerrno>
#include <csetjmp>
#include <cstdio>  // before jpeglib.h, which uses FILE and size_t

#include <jpeglib.h>
#include <png.h>
#include <cstring>
#include <fstream>
#include <iterator>

#include "megavox/error.h"

namespace mv::io {

namespace {

[[noreturn]] void fail(const std::string& name, const std::string& why) {
  throw Error("image '" + name + "': " + why);
}

void check_size(const std::string& name, uint64_t w, uint64_t h) {
  if (w == 0 || h == 0) fail(name, "it has no pixels");
  if (w * h > kMaxImagePixels)
    fail(name, std::to_string(w) + " x " + std::to_string(h) + " pixels is over the " +
                   std::to_string(kMaxImagePixels) + " a mask takes");
}

// ---- PNM (P5 grey, P6 RGB; maxval up to 65535, 16-bit samples big-endian) ----

RasterImage decode_pnm(std::span<const uint8_t> b, const std::string& name) {
  size_t at = 2;
  auto skip_space = [&] {
    for (;;) {
      while (at < b.size() && std::strchr(" \t\r\n\v\f", b[at]) && b[at]) ++at;
      if (at < b.size() && b[at] == '#') {
        while (at < b.size() && b[at] != '\n') ++at;
        continue;
      }
      return;
    }
  };
  auto number = [&](const char* what) {
    skip_space();
    uint64_t v = 0;
    size_t digits = 0;
    while (at < b.size() && b[at] >= '0' && b[at] <= '9' && digits < 10) v = v * 10 + (b[at++] - '0'), ++digits;
    if (digits == 0 || (at < b.size() && b[at] >= '0' && b[at] <= '9'))
      fail(name, std::string("the PNM header's ") + what + " is missing or too long");
    return v;
  };
  const uint32_t channels = b[1] == '6' ? 3 : 1;
  const uint64_t w = number("width"), h = number("height"), maxval = number("maxval");
  if (maxval == 0 || maxval > 65535) fail(name, "PNM maxval " + std::to_string(maxval) + " (1 to 65535 expected)");
  check_size(name, w, h);
  if (at >= b.size() || !std::strchr(" \t\r\n\v\f", b[at]) || !b[at]) fail(name, "the PNM header does not end in a space");
  ++at;
  const uint64_t bytes_per = maxval > 255 ? 2 : 1, samples = w * h * channels;
  if (b.size() - at < samples * bytes_per)
    fail(name, "truncated: " + std::to_string(samples * bytes_per) + " bytes of pixels expected, " +
                   std::to_string(b.size() - at) + " there");
  RasterImage img{static_cast<uint32_t>(w), static_cast<uint32_t>(h), channels, static_cast<uint32_t>(maxval), {}};
  img.samples.resize(samples);
  for (uint64_t i = 0; i < samples; ++i) {
    const uint16_t v = bytes_per == 2 ? uint16_t(b[at + 2 * i] << 8 | b[at + 2 * i + 1]) : b[at + i];
    if (v > maxval) fail(name, "a sample of " + std::to_string(v) + " is over the PNM maxval " + std::to_string(maxval));
    img.samples[i] = v;
  }
  return img;
}

// ---- PNG ----

struct PngRead {
  std::span<const uint8_t> bytes;
  size_t at = 0;
  png_bytep row = nullptr;  // here, not a local: it must survive the longjmp
  char message[200] = "";
};

void png_read_bytes(png_structp png, png_bytep out, png_size_t n) {
  auto* r = static_cast<PngRead*>(png_get_io_ptr(png));
  if (r->bytes.size() - r->at < n) png_error(png, "truncated file");
  std::memcpy(out, r->bytes.data() + r->at, n);
  r->at += n;
}

void png_error_text(png_structp png, png_const_charp msg) {
  auto* r = static_cast<PngRead*>(png_get_error_ptr(png));
  std::snprintf(r->message, sizeof r->message, "%s", msg);
  png_longjmp(png, 1);
}

void png_no_warning(png_structp, png_const_charp) {}

// Fills w, h, channels, bits, then (after `size_ok` approves the size) pixels; false with r.message on failure.
bool png_decode(PngRead& r, uint32_t& w, uint32_t& h, uint32_t& channels, uint32_t& bits,
                std::vector<uint16_t>* pixels, bool (*size_ok)(uint32_t, uint32_t)) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &r, png_error_text, png_no_warning);
  if (!png) return false;
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    std::free(r.row);
    r.row = nullptr;
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_set_read_fn(png, &r, png_read_bytes);
  png_set_user_limits(png, 1u << 24, 1u << 24);
  png_read_info(png, info);
  w = png_get_image_width(png, info);
  h = png_get_image_height(png, info);
  if (!size_ok(w, h)) png_error(png, "too many pixels");
  png_set_expand(png);  // palette to RGB, grey below 8 bits to 8, tRNS to alpha
  png_set_strip_alpha(png);
  if (png_get_bit_depth(png, info) == 16) png_set_swap(png);  // host order (little-endian)
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  channels = png_get_channels(png, info);
  bits = png_get_bit_depth(png, info);
  if ((channels != 1 && channels != 3) || (bits != 8 && bits != 16)) png_error(png, "unsupported colour layout");
  r.row = static_cast<png_bytep>(std::malloc(png_get_rowbytes(png, info)));
  if (!r.row) png_error(png, "out of memory");
  png_bytep row = r.row;
  const int passes = png_set_interlace_handling(png);
  pixels->assign(size_t{w} * h * channels, 0);
  for (int pass = 0; pass < passes; ++pass)
    for (uint32_t y = 0; y < h; ++y) {
      // Interlaced images are read whole per pass: rows carry the previous pass's pixels in.
      uint16_t* dst = pixels->data() + size_t{y} * w * channels;
      for (size_t k = 0; k < size_t{w} * channels; ++k) {
        if (bits == 16) std::memcpy(row + 2 * k, &dst[k], 2);
        else row[k] = static_cast<png_byte>(dst[k]);
      }
      png_read_row(png, row, nullptr);
      for (size_t k = 0; k < size_t{w} * channels; ++k) {
        if (bits == 16) std::memcpy(&dst[k], row + 2 * k, 2);
        else dst[k] = row[k];
      }
    }
  png_read_end(png, nullptr);
  std::free(r.row);
  r.row = nullptr;
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

bool pixels_ok(uint32_t w, uint32_t h) { return w > 0 && h > 0 && uint64_t{w} * h <= kMaxImagePixels; }

RasterImage decode_png(std::span<const uint8_t> b, const std::string& name) {
  PngRead r{b};
  RasterImage img;
  uint32_t bits = 8;
  if (!png_decode(r, img.width, img.height, img.channels, bits, &img.samples, pixels_ok)) {
    if (img.width && img.height) check_size(name, img.width, img.height);
    fail(name, std::string("PNG: ") + (r.message[0] ? r.message : "libpng failed"));
  }
  img.max_value = bits == 16 ? 65535 : 255;
  return img;
}

// ---- JPEG ----

struct JpegError {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
  JSAMPLE* row = nullptr;  // here, not a local: it must survive the longjmp
  char message[JMSG_LENGTH_MAX] = "";
};

void jpeg_exit(j_common_ptr cinfo) {
  auto* e = reinterpret_cast<JpegError*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, e->message);
  std::longjmp(e->jump, 1);
}

void jpeg_quiet(j_common_ptr, int) {}

bool jpeg_decode(std::span<const uint8_t> b, JpegError& err, uint32_t& w, uint32_t& h, uint32_t& channels,
                 std::vector<uint16_t>* pixels) {
  jpeg_decompress_struct cinfo;
  cinfo.err = jpeg_std_error(&err.mgr);
  err.mgr.error_exit = jpeg_exit;
  err.mgr.emit_message = jpeg_quiet;
  if (setjmp(err.jump)) {
    std::free(err.row);
    err.row = nullptr;
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  jpeg_create_decompress(&cinfo);
  jpeg_mem_src(&cinfo, b.data(), static_cast<unsigned long>(b.size()));
  jpeg_read_header(&cinfo, TRUE);
  w = cinfo.image_width;
  h = cinfo.image_height;
  if (!pixels_ok(w, h)) {
    std::snprintf(err.message, sizeof err.message, "too many pixels");
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  cinfo.out_color_space = cinfo.num_components == 1 ? JCS_GRAYSCALE : JCS_RGB;
  jpeg_start_decompress(&cinfo);
  channels = static_cast<uint32_t>(cinfo.output_components);
  err.row = static_cast<JSAMPLE*>(std::malloc(size_t{w} * channels));
  if (!err.row) {
    std::snprintf(err.message, sizeof err.message, "out of memory");
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  JSAMPLE* row = err.row;
  pixels->assign(size_t{w} * h * channels, 0);
  while (cinfo.output_scanline < cinfo.output_height) {
    const uint32_t y = cinfo.output_scanline;
    jpeg_read_scanlines(&cinfo, &row, 1);
    for (size_t k = 0; k < size_t{w} * channels; ++k) (*pixels)[size_t{y} * w * channels + k] = row[k];
  }
  jpeg_finish_decompress(&cinfo);
  std::free(err.row);
  err.row = nullptr;
  jpeg_destroy_decompress(&cinfo);
  return true;
}

RasterImage decode_jpeg(std::span<const uint8_t> b, const std::string& name) {
  JpegError err;
  RasterImage img;
  if (!jpeg_decode(b, err, img.width, img.height, img.channels, &img.samples)) {
    if (img.width && img.height) check_size(name, img.width, img.height);
    fail(name, std::string("JPEG: ") + err.message);
  }
  return img;
}

std::vector<uint8_t> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot open image '" + path + "': " + std::strerror(errno));
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw IoError("cannot read image '" + path + "'");
  return bytes;
}

}  // namespace

RasterImage decode_image(std::span<const uint8_t> b, const std::string& name) {
  static const uint8_t png_magic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (b.size() >= 8 && std::memcmp(b.data(), png_magic, 8) == 0) return decode_png(b, name);
  if (b.size() >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff) return decode_jpeg(b, name);
  if (b.size() >= 2 && b[0] == 'P' && (b[1] == '5' || b[1] == '6')) return decode_pnm(b, name);
  if (b.size() >= 2 && b[0] == 'P' && b[1] >= '1' && b[1] <= '4')
    fail(name, "ASCII or 1-bit PNM (P1-P4) is not read: write binary PGM (P5) or PPM (P6)");
  fail(name, b.empty() ? "the file is empty" : "not a PNG, JPEG, PPM (P6) or PGM (P5) file");
}

RasterImage read_image(const std::string& path) { return decode_image(file_bytes(path), path); }

std::vector<uint8_t> decode_seed_map(std::span<const uint8_t> bytes, const std::string& name, uint32_t width,
                                     uint32_t height) {
  const RasterImage img = decode_image(bytes, name);
  if (img.channels != 1 || img.max_value != 255)
    throw Error("seed map '" + name + "': an 8-bit one-channel image is expected (0, 64, 128, 192, 255)");
  if (img.width != width || img.height != height)
    throw Error("seed map '" + name + "' is " + std::to_string(img.width) + " x " + std::to_string(img.height) +
                ", its image " + std::to_string(width) + " x " + std::to_string(height));
  std::vector<uint8_t> seeds(img.samples.size());
  for (size_t i = 0; i < seeds.size(); ++i) {
    const uint16_t v = img.samples[i];
    if (v != 0 && v != 64 && v != 128 && v != 192 && v != 255)
      throw Error("seed map '" + name + "': value " + std::to_string(v) + " at (" + std::to_string(i % width) +
                  ", " + std::to_string(i / width) + "); only 0, 64, 128, 192 and 255 have a meaning");
    seeds[i] = static_cast<uint8_t>(v);
  }
  return seeds;
}

std::vector<uint8_t> read_seed_map(const std::string& path, uint32_t width, uint32_t height) {
  return decode_seed_map(file_bytes(path), path, width, height);
}

}  // namespace mv::io
