// decode_image and decode_seed_map (host/formats/io/image_reader.h): PNG through libpng, JPEG through libjpeg-turbo,
// binary PNM by megavox's parser; the format is told from the content. The same bytes are then read as a seed
// map of the size they declare (so a valid map passes the value checks too).
#include <vector>

#include "fuzz_support.h"
#include "io/image_reader.h"
#include "megavox/error.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::span<const uint8_t> bytes(data, size);
  try {
    const mv::RasterImage img = mv::io::decode_image(bytes, "input");
    MV_FUZZ_CHECK(img.width > 0 && img.height > 0 && (img.channels == 1 || img.channels == 3));
    MV_FUZZ_CHECK(uint64_t{img.width} * img.height <= mv::io::kMaxImagePixels);
    MV_FUZZ_CHECK(img.samples.size() == size_t{img.width} * img.height * img.channels);
    for (uint16_t s : img.samples) MV_FUZZ_CHECK(s <= img.max_value);
    const std::vector<uint8_t> seeds = mv::io::decode_seed_map(bytes, "input", img.width, img.height);
    for (uint8_t v : seeds) MV_FUZZ_CHECK(v == 0 || v == 64 || v == 128 || v == 192 || v == 255);
  } catch (const mv::Error&) {
  }
  return 0;
}
