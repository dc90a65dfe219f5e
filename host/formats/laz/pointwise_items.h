// The item coders of LAZ's pointwise compressors (LAS point formats 0-5): each item of a record has its own
// models and its own memory of the previous point, and all of them read one shared arithmetic stream, item
// after item, point after point. The first point of a chunk is stored raw, ahead of the stream.
//
// Versions: 1 (LASzip 1.0-1.3) and 2 (LASzip 2.0 on) of POINT10, GPSTIME11, RGB12 and BYTE10. The coders of
// one version share nothing with the other's; pointwise_chunk.cpp picks them from the schema.
#pragma once
#include <cstdint>
#include <memory>

#include "laz_schema.h"

namespace mv::laz {

class PointwiseItem {
 public:
  virtual ~PointwiseItem() = default;
  // The chunk's first record of this item, as stored raw.
  virtual void first(const uint8_t* raw) = 0;
  // The next record of this item, decoded from `dec` into `out` (the item's size in bytes).
  virtual void next(ArithmeticDecoder& dec, uint8_t* out) = 0;
};

// A fresh coder (every model at its initial state) for `item`; throws LazError for a type or version that the
// pointwise compressors do not define.
std::unique_ptr<PointwiseItem> make_pointwise_v1(const Item& item);
std::unique_ptr<PointwiseItem> make_pointwise_v2(const Item& item);

}  // namespace mv::laz
