// Photographs and range maps in: PNG (libpng), JPEG (libjpeg-turbo), binary PPM (P6) and PGM (P5), 8- or
// 16-bit. The format is told from the content, never the name. Bad or truncated bytes throw mv::Error naming
// the file and what is wrong.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "megavox/raster.h"

namespace mv::io {

// Pixels over this are refused before anything is allocated (a 16 K x 16 K photograph; 2 K x 2 K when fuzzing).
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
inline constexpr uint64_t kMaxImagePixels = uint64_t{1} << 22;
#else
inline constexpr uint64_t kMaxImagePixels = uint64_t{1} << 28;
#endif

// `name` says where the bytes came from in messages.
RasterImage decode_image(std::span<const uint8_t> bytes, const std::string& name);
RasterImage read_image(const std::string& path);

// A seed map (trimap or strokes): a one-channel 8-bit image whose values are 0 (sure background), 64
// (probable background), 128 (unknown), 192 (probable foreground) or 255 (sure foreground), of the given
// size. Anything else (another size, colour, 16 bits, another value) throws mv::Error saying where.
std::vector<uint8_t> decode_seed_map(std::span<const uint8_t> bytes, const std::string& name, uint32_t width,
                                     uint32_t height);
std::vector<uint8_t> read_seed_map(const std::string& path, uint32_t width, uint32_t height);

}  // namespace mv::io
