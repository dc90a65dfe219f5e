// The POINT14 item coder of LAZ's layered compressor (LAS 1.4 point formats 6-10, LASzip item version 3):
// the 30-byte core of a LAS 1.4 point record, stored per chunk as nine separately coded layers -- scanner
// channel, returns and X/Y together; Z; classification; flags; intensity; scan angle; user data; point source
// ID; GPS time -- so that a layer whose field never changes in the chunk is empty and costs nothing.
//
// Every model and every "previous point" lives in one of four contexts, one per scanner channel: a channel's
// context is created the first time the chunk's points switch to it, from the last point of the channel they
// came from. POINT14 also picks the context of the record's other items (RGB14, RGBNIR14, BYTE14), which the
// chunk decoder hands on to them after each point (items_context()): the first point's channel, then
//   version 3: the new channel on a point that switches channel, and context 0 on every other point (LASzip's
//              reader restarts the context at 0 for each point and version 3 sets it only on a switch -- a
//              quirk its writer shares, so it is part of the format);
//   version 4: the point's channel, always.
// Otherwise version 4 decodes exactly as version 3, and LASzip reads version 2 (its prototype number for the
// same coder) as version 3.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>

#include "arithmetic_decoder.h"

namespace mv::laz {

// The stored bytes of one layer; an empty layer means its field does not change in the whole chunk.
struct LayerBytes {
  const uint8_t* begin = nullptr;
  const uint8_t* end = nullptr;
  bool empty() const { return begin == end; }
};

// A decoder over one layer's bytes, or none for an empty layer. A layer too short for the coder's first four
// bytes throws LazError (every encoder pads its layers so that the decoder never reads past their end).
std::optional<ArithmeticDecoder> open_layer(LayerBytes layer, const char* what);

class Point14Decoder {
 public:
  static constexpr uint16_t kRecordBytes = 30;
  static constexpr size_t kLayers = 9;

  // `first`: the chunk's first record of this item, as stored raw; `layers`: its kLayers layers in stored order;
  // `version`: the item version (2 to 4).
  Point14Decoder(const uint8_t* first, const LayerBytes* layers, uint16_t version);
  ~Point14Decoder();
  Point14Decoder(const Point14Decoder&) = delete;
  Point14Decoder& operator=(const Point14Decoder&) = delete;

  // Decodes the chunk's next point into `out` (kRecordBytes bytes, LAS 1.4 layout).
  void next(uint8_t* out);

  // The context (0-3) the last point decoded hands to the record's other items.
  unsigned items_context() const { return items_context_; }

  // Bytes asked for past the end of any layer; a sound chunk asks for none.
  size_t overrun() const;

  struct Fields;
  struct Channel;

 private:
  Channel& open_channel(unsigned channel, const Fields& from);
  uint64_t decode_gps_time(Channel& ch, ArithmeticDecoder& dec);

  std::optional<ArithmeticDecoder> xy_, z_, classification_, flags_, intensity_, scan_angle_, user_data_,
      point_source_, gps_time_;
  std::unique_ptr<Channel> channels_[4];
  unsigned current_ = 0;        // the scanner channel of the last point
  unsigned items_context_ = 0;  // see items_context()
  bool hand_on_channel_;        // version 4: every point hands on its channel
};

}  // namespace mv::laz
