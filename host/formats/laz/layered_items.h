// The item coders that ride along with POINT14 in LAZ's layered compressor (LASzip item version 3): RGB14
// (red, green, blue: 6 bytes), RGBNIR14 (the same plus near infrared: 8 bytes) and BYTE14 (extra bytes, each
// byte its own layer). Each keeps four contexts and uses, for each point, the one the POINT14 coder hands on
// (Point14Decoder::items_context()); a context is created the first time it is used, from the values of the
// context used before it.
//
// LASzip version 3 has a quirk that is part of its format (its writer shares it): on a switch to a context
// that already exists, the point is predicted from (and then stored as) the previous context's last value, not
// the new context's. Version 4 of these items fixes that, so it decodes differently and is not read here.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "point14_item.h"

namespace mv::laz {

// RGB14 (with_nir false, 1 layer) or RGBNIR14 (with_nir true, 2 layers: RGB, NIR).
class ColourDecoder {
 public:
  // `first`: the chunk's first record of this item, as stored raw; `context`: the first point's context.
  ColourDecoder(const uint8_t* first, unsigned context, bool with_nir, const LayerBytes* layers);
  ~ColourDecoder();
  ColourDecoder(const ColourDecoder&) = delete;
  ColourDecoder& operator=(const ColourDecoder&) = delete;

  static size_t layers(bool with_nir) { return with_nir ? 2 : 1; }

  // The next record (6 or 8 bytes), of a point in context `context` (0-3).
  void next(unsigned context, uint8_t* out);
  size_t overrun() const;

  struct Context;

 private:
  Context& open_context(unsigned context, const uint16_t* from);

  std::optional<ArithmeticDecoder> rgb_, nir_;
  std::unique_ptr<Context> contexts_[4];
  unsigned current_;
  bool with_nir_;
};

// BYTE14 of `size` bytes (size layers).
class Byte14Decoder {
 public:
  Byte14Decoder(const uint8_t* first, unsigned context, uint16_t size, const LayerBytes* layers);
  ~Byte14Decoder();
  Byte14Decoder(const Byte14Decoder&) = delete;
  Byte14Decoder& operator=(const Byte14Decoder&) = delete;

  void next(unsigned context, uint8_t* out);
  size_t overrun() const;

  struct Context;

 private:
  Context& open_context(unsigned context, const uint8_t* from);

  uint16_t size_;
  std::vector<uint16_t> coded_;              // the bytes whose layer is not empty
  std::vector<ArithmeticDecoder> decoders_;  // one per coded byte
  std::unique_ptr<Context> contexts_[4];
  unsigned current_;
};

}  // namespace mv::laz
