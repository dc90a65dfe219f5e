// Seeds of the mask readers (fuzz_image, fuzz_mvm), written by make_seeds.cpp: PNM (8- and 16-bit, grey and
// RGB, with a comment), PNG (grey 8, grey 16, RGB) and JPEG (grey, RGB) images, a seed map, and .mvm models of
// both channel counts; each read back through its reader before it is kept.
#pragma once

#include <png.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "../tests/jpeg_encode.h"
#include "io/image_reader.h"
#include "io/mvm_file.h"
#include "io/png_grey.h"
#include "megavox/image.h"

namespace mask_seeds {

inline void put_file(const std::filesystem::path& p, const std::vector<uint8_t>& b) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}

inline std::vector<uint8_t> jpeg_bytes(uint32_t w, uint32_t h, int channels) {
  std::vector<uint8_t> px(size_t{w} * h * channels);
  for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t(i * 37 % 251);
  return mv::test::encode_jpeg(w, h, channels, px, 60);
}

inline std::vector<uint8_t> read_back(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void write(const std::filesystem::path& out) {
  const auto img = out / "fuzz_image", mvm = out / "fuzz_mvm";
  std::vector<std::filesystem::path> images;
  auto pnm = [&](const std::string& name, const std::string& header, const std::vector<uint8_t>& px) {
    std::vector<uint8_t> b(header.begin(), header.end());
    b.insert(b.end(), px.begin(), px.end());
    put_file(img / name, b);
    images.push_back(img / name);
  };
  pnm("grey8.pgm", "P5\n# seed\n4 3\n255\n", {0, 64, 128, 192, 255, 128, 0, 64, 128, 192, 255, 255});
  pnm("grey16.pgm", "P5 2 2 65535\n", {0, 0, 1, 2, 255, 255, 16, 0});
  pnm("rgb8.ppm", "P6\n2 2\n200\n", {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12});
  mv::io::write_png_grey((img / "seeds.png").string(), 4, 2, {0, 64, 128, 192, 255, 128, 0, 255});
  images.push_back(img / "seeds.png");
  mv::Image rgb;
  rgb.width = 3, rgb.height = 2, rgb.rgb = {10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120, 130, 140, 150, 160, 170, 180};
  mv::write_png((img / "rgb.png").string(), rgb);
  images.push_back(img / "rgb.png");
  {  // 16-bit grey PNG by libpng directly
    const std::string p = (img / "grey16.png").string();
    std::FILE* f = std::fopen(p.c_str(), "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    png_init_io(png, f);
    png_set_IHDR(png, info, 2, 2, 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    uint8_t rows[2][4] = {{0, 1, 2, 3}, {255, 255, 128, 0}};
    png_write_row(png, rows[0]);
    png_write_row(png, rows[1]);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    images.push_back(p);
  }
  put_file(img / "grey.jpg", jpeg_bytes(8, 8, 1));
  put_file(img / "rgb.jpg", jpeg_bytes(9, 5, 3));
  images.push_back(img / "grey.jpg");
  images.push_back(img / "rgb.jpg");
  for (const auto& p : images) {
    const mv::RasterImage r = mv::io::decode_image(read_back(p), p.string());
    if (r.samples.size() != size_t{r.width} * r.height * r.channels) throw std::runtime_error(p.string() + ": samples");
    std::printf("  %-50s %6llu bytes\n", p.c_str(), (unsigned long long)std::filesystem::file_size(p));
  }
  for (uint32_t ch : {1u, 3u}) {
    mv::MaskModel m = mv::MaskModel::empty(ch);
    for (uint32_t b = 0; b < m.bins(); b += 3) m.fg[b] = b + 1, m.bg[b + (b + 1 < m.bins())] = 2 * b + 1;
    const auto p = mvm / (ch == 1 ? "grey.mvm" : "colour.mvm");
    std::filesystem::create_directories(mvm);
    mv::io::write_mvm(p.string(), m);
    if (mv::io::read_mvm(p.string()).fg != m.fg) throw std::runtime_error(p.string() + ": read back");
    std::printf("  %-50s %6llu bytes\n", p.c_str(), (unsigned long long)std::filesystem::file_size(p));
  }
}

}  // namespace mask_seeds
