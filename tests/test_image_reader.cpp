// Image and seed-map reading: PNM, PNG (libpng) and JPEG (libjpeg-turbo) written here, the shared data's
// photographs and 16-bit range maps, and bad bytes of every kind refused with a message that says why.
#include <cstdio>  // before jpeglib.h, which uses FILE and size_t
#include <fstream>

#include <jpeglib.h>
#include <png.h>

#include "io/image_reader.h"
#include "megavox/render.h"
#include "jpeg_encode.h"
#include "test_support.h"

namespace mv::test {
namespace {

std::vector<uint8_t> bytes_of(const std::string& s) { return {s.begin(), s.end()}; }

std::vector<uint8_t> read_all(const std::string& path) {
  std::vector<char> c = file_bytes(path);
  return {c.begin(), c.end()};
}

// A one-channel PNG of `bits` (8 or 16) through libpng, samples given in host order.
std::string write_grey_png(const std::string& name, uint32_t w, uint32_t h, int bits, const std::vector<uint16_t>& v) {
  const std::string path = temp_path(name);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_set_IHDR(png, info, w, h, bits, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  std::vector<uint8_t> row(size_t{w} * bits / 8);
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      const uint16_t s = v[size_t{y} * w + x];
      if (bits == 16) row[2 * x] = uint8_t(s >> 8), row[2 * x + 1] = uint8_t(s);  // PNG is big-endian
      else row[x] = uint8_t(s);
    }
    png_write_row(png, row.data());
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
  return path;
}

TEST(ImageReader, PnmEightAndSixteenBit) {
  std::string p6 = "P6\n# a comment\n3 2\n255\n";
  for (int i = 0; i < 18; ++i) p6 += char(i * 13);
  RasterImage a = io::decode_image(bytes_of(p6), "a.ppm");
  EXPECT_EQ(a.width, 3u);
  EXPECT_EQ(a.height, 2u);
  EXPECT_EQ(a.channels, 3u);
  EXPECT_EQ(a.max_value, 255u);
  for (int i = 0; i < 18; ++i) EXPECT_EQ(a.samples[i], uint16_t(uint8_t(i * 13)));
  std::string p5 = "P5 2 2 65535\n";
  for (uint16_t v : {0, 1, 0x1234, 65535}) p5 += char(v >> 8), p5 += char(v & 255);
  RasterImage b = io::decode_image(bytes_of(p5), "b.pgm");
  EXPECT_EQ(b.channels, 1u);
  EXPECT_EQ(b.max_value, 65535u);
  EXPECT_EQ(b.samples, (std::vector<uint16_t>{0, 1, 0x1234, 65535}));
}

TEST(ImageReader, PngRgbGreyAndSixteenBit) {
  Image rgb;
  rgb.width = 5;
  rgb.height = 4;
  for (int i = 0; i < 60; ++i) rgb.rgb.push_back(uint8_t(i * 7));
  const std::string path = temp_path("rgb.png");
  write_png(path, rgb);
  RasterImage a = io::read_image(path);
  ASSERT_EQ(a.channels, 3u);
  EXPECT_EQ(a.width, 5u);
  for (int i = 0; i < 60; ++i) EXPECT_EQ(a.samples[i], rgb.rgb[i]);
  std::vector<uint16_t> v = {0, 300, 65535, 4096, 7, 65000};
  RasterImage b = io::read_image(write_grey_png("g16.png", 3, 2, 16, v));
  EXPECT_EQ(b.max_value, 65535u);
  EXPECT_EQ(b.samples, v);
  std::vector<uint16_t> v8 = {0, 64, 128, 192, 255, 255};
  RasterImage c = io::read_image(write_grey_png("g8.png", 2, 3, 8, v8));
  EXPECT_EQ(c.max_value, 255u);
  EXPECT_EQ(c.samples, v8);
}

TEST(ImageReader, JpegRgbAndGrey) {
  std::vector<uint8_t> px(16 * 8 * 3, 0);
  for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t(i % 3 == 0 ? 200 : 40);  // flat colour: near exact
  RasterImage a = io::decode_image(encode_jpeg(16, 8, 3, px), "a.jpg");
  ASSERT_EQ(a.channels, 3u);
  EXPECT_EQ(a.width, 16u);
  EXPECT_EQ(a.height, 8u);
  for (size_t i = 0; i < px.size(); ++i) EXPECT_NEAR(a.samples[i], px[i], 3) << i;
  RasterImage b = io::decode_image(encode_jpeg(9, 7, 1, std::vector<uint8_t>(63, 90)), "b.jpg");
  ASSERT_EQ(b.channels, 1u);
  for (uint16_t s : b.samples) EXPECT_NEAR(s, 90, 2);
}

TEST(ImageReader, BadBytesSayWhy) {
  auto why = [](const std::vector<uint8_t>& b) { return error_message([&] { io::decode_image(b, "x"); }); };
  EXPECT_NE(why({}).find("empty"), std::string::npos);
  EXPECT_NE(why(bytes_of("hello")).find("not a PNG, JPEG"), std::string::npos);
  EXPECT_NE(why(bytes_of("P2 1 1 255 7")).find("ASCII"), std::string::npos);
  EXPECT_NE(why(bytes_of("P5 2 2 255\nab")).find("truncated"), std::string::npos);
  EXPECT_NE(why(bytes_of("P5 2 2 0\nabcd")).find("maxval"), std::string::npos);
  EXPECT_NE(why(bytes_of("P5 2 2 9\nabcd")).find("over the PNM maxval"), std::string::npos);
  EXPECT_NE(why(bytes_of("P5 0 2 255\n")).find("no pixels"), std::string::npos);
  EXPECT_NE(why(bytes_of("P6 99999 99999 255\n")).find("pixels is over"), std::string::npos);
  EXPECT_NE(why(bytes_of("P5 2 x 255\n")).find("height"), std::string::npos);
  std::vector<uint8_t> png = read_all(write_grey_png("cut.png", 40, 30, 8, std::vector<uint16_t>(1200, 9)));
  png.resize(png.size() / 2);
  EXPECT_NE(why(png).find("PNG"), std::string::npos);
  std::vector<uint8_t> jpg = encode_jpeg(40, 30, 1, std::vector<uint8_t>(1200, 9));
  jpg.resize(jpg.size() / 2);
  // libjpeg pads a truncated stream with an end marker and warns; cut into the header instead.
  jpg.resize(20);
  EXPECT_NE(why(jpg).find("JPEG"), std::string::npos);
  EXPECT_NE(error_message([] { io::read_image("/nonexistent/image.png"); }).find("cannot open"), std::string::npos);
}

TEST(ImageReader, SeedMaps) {
  std::vector<uint16_t> v = {0, 64, 128, 192, 255, 128};
  const std::string ok = write_grey_png("seeds.png", 3, 2, 8, v);
  EXPECT_EQ(io::read_seed_map(ok, 3, 2), (std::vector<uint8_t>{0, 64, 128, 192, 255, 128}));
  EXPECT_NE(error_message([&] { io::read_seed_map(ok, 2, 3); }).find("is 3 x 2, its image 2 x 3"), std::string::npos);
  v[4] = 200;
  const std::string bad = write_grey_png("bad_seeds.png", 3, 2, 8, v);
  EXPECT_NE(error_message([&] { io::read_seed_map(bad, 3, 2); }).find("value 200 at (1, 1)"), std::string::npos);
  const std::string wide = write_grey_png("seeds16.png", 3, 2, 16, {0, 0, 0, 0, 0, 0});
  EXPECT_NE(error_message([&] { io::read_seed_map(wide, 3, 2); }).find("8-bit one-channel"), std::string::npos);
}

TEST(ImageReader, SharedPhotographsAndRangeMaps) {
  MV_SKIP_WITHOUT_SHARED_DATA("grabcut/images/llama.ppm");
  RasterImage photo = io::read_image(shared_data_file("grabcut/images/llama.ppm"));
  EXPECT_EQ(photo.channels, 3u);
  EXPECT_GT(photo.width, 100u);
  RasterImage mask = io::read_image(shared_data_file("grabcut/masks/llama.pgm"));
  EXPECT_EQ(mask.channels, 1u);
  EXPECT_EQ(mask.width, photo.width);
  EXPECT_EQ(mask.height, photo.height);
  MV_SKIP_WITHOUT_SHARED_DATA("rgbd_kinect/tum_desk_depth_raw.pgm");
  RasterImage range = io::read_image(shared_data_file("rgbd_kinect/tum_desk_depth_raw.pgm"));
  EXPECT_EQ(range.max_value, 65535u);
  EXPECT_EQ(range.channels, 1u);
  EXPECT_GT(*std::max_element(range.samples.begin(), range.samples.end()), 255u);
}

}  // namespace
}  // namespace mv::test
