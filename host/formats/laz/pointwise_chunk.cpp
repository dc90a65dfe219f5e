// A chunk of a pointwise compressor: the first record raw, then one arithmetic stream that every item reads in
// turn, record after record. Also the LASzip record's parsing into a Schema, shared by both compressors.
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "laz_schema.h"
#include "pointwise_items.h"

namespace mv::laz {

namespace {

std::string n_of(uint64_t v) { return std::to_string(v); }

uint16_t schema_u16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
uint32_t schema_u32(const uint8_t* p) {
  return p[0] | (p[1] << 8) | (p[2] << 16) | (static_cast<uint32_t>(p[3]) << 24);
}

const char* item_name(ItemType t) {
  switch (t) {
    case ItemType::byte10: return "BYTE";
    case ItemType::point10: return "POINT10";
    case ItemType::gpstime11: return "GPSTIME11";
    case ItemType::rgb12: return "RGB12";
    case ItemType::wavepacket13: return "WAVEPACKET13";
    case ItemType::point14: return "POINT14";
    case ItemType::rgb14: return "RGB14";
    case ItemType::rgbnir14: return "RGBNIR14";
    case ItemType::wavepacket14: return "WAVEPACKET14";
    case ItemType::byte14: return "BYTE14";
  }
  return "unknown";
}

// The items a point format is made of, before any extra bytes.
std::vector<ItemType> items_of(unsigned format) {
  using T = ItemType;
  switch (format) {
    case 0: return {T::point10};
    case 1: return {T::point10, T::gpstime11};
    case 2: return {T::point10, T::rgb12};
    case 3: return {T::point10, T::gpstime11, T::rgb12};
    case 6: return {T::point14};
    case 7: return {T::point14, T::rgb14};
    case 8: return {T::point14, T::rgbnir14};
    default: return {};
  }
}

}  // namespace

Schema parse_schema(const uint8_t* b, size_t size, unsigned point_format, uint32_t record_length) {
  if (size < 34) throw LazError("the LASzip record has " + n_of(size) + " bytes, fewer than the 34 of its header");
  Schema s;
  const uint16_t compressor = schema_u16(b);
  if (compressor < 1 || compressor > 3)
    throw LazError("unknown LAZ compressor " + n_of(compressor) +
                   " (1: pointwise, 2: pointwise chunked, 3: layered chunked are defined)");
  s.compressor = static_cast<Compressor>(compressor);
  s.coder = schema_u16(b + 2);
  if (s.coder != 0) throw LazError("unknown LAZ coder " + n_of(s.coder) + " (only 0, arithmetic, is defined)");
  s.version_major = b[4];
  s.version_minor = b[5];
  s.version_revision = schema_u16(b + 6);
  s.options = schema_u32(b + 8);
  s.chunk_size = schema_u32(b + 12);
  const uint16_t count = schema_u16(b + 32);
  if (34 + 6ull * count > size)
    throw LazError("the LASzip record lists " + n_of(count) + " items but has room for " + n_of((size - 34) / 6));
  for (uint16_t i = 0; i < count; ++i) {
    const uint8_t* p = b + 34 + 6 * i;
    s.items.push_back({static_cast<ItemType>(schema_u16(p)), schema_u16(p + 2), schema_u16(p + 4)});
    s.record_length += s.items.back().size;
  }
  if (s.chunked() && s.chunk_size == 0) throw LazError("a chunked LAZ compressor with chunks of 0 points");

  // The items must compose the point format's record, in order, with at most one item of extra bytes.
  const std::vector<ItemType> expected = items_of(point_format);
  if (expected.empty())
    throw LazError("point format " + n_of(point_format) + " is not read from LAZ" +
                   (point_format == 4 || point_format == 5 || point_format == 9 || point_format == 10
                        ? std::string(" (its waveform packets' LAZ items are not decoded; uncompressed, it is read)")
                        : std::string()));
  const bool layered_format = point_format >= 6;
  if (s.layered() != layered_format)
    throw LazError(std::string("point format ") + n_of(point_format) + " with the " +
                   (s.layered() ? "layered" : "pointwise") + " compressor (formats 0-5 are pointwise, 6-10 layered)");
  auto listed = [&] {
    std::string out;
    for (const Item& it : s.items) out += std::string(out.empty() ? "" : ", ") + item_name(it.type) + " v" + n_of(it.version);
    return out.empty() ? std::string("none") : out;
  };
  bool matches = s.items.size() == expected.size() || s.items.size() == expected.size() + 1;
  for (size_t i = 0; matches && i < s.items.size(); ++i) {
    const ItemType want = i < expected.size() ? expected[i] : (layered_format ? ItemType::byte14 : ItemType::byte10);
    matches = s.items[i].type == want;
  }
  if (!matches) throw LazError("the LAZ items (" + listed() + ") do not make point format " + n_of(point_format));
  if (s.record_length != record_length)
    throw LazError("the LAZ items (" + listed() + ") make records of " + n_of(s.record_length) +
                   " bytes, the LAS header says " + n_of(record_length));
  for (const Item& it : s.items) {
    // The layered decoder checks its items' versions (2 to 4) itself, item by item.
    const bool known = s.layered() ? (it.version >= 2 && it.version <= 4) : (it.version == 1 || it.version == 2);
    if (!known)
      throw LazError(std::string("LAZ item ") + item_name(it.type) + " version " + n_of(it.version) +
                     " is not read (pointwise items have versions 1 and 2, layered ones 2 to 4)");
  }
  return s;
}

namespace {

class PointwiseChunk final : public ChunkDecoder {
 public:
  PointwiseChunk(const Schema& schema, const uint8_t* bytes, size_t size, uint64_t points)
      : schema_(schema), bytes_(bytes), size_(size), points_(points) {
    const uint32_t length = schema.record_length;
    if (points == 0) throw LazError("a chunk of no points");
    if (size < length + 4ull)
      throw LazError("a chunk of " + n_of(size) + " bytes cannot hold its first point and its coder's start");
    for (const Item& it : schema.items)
      items_.push_back(it.version == 1 ? make_pointwise_v1(it) : make_pointwise_v2(it));
    const uint8_t* raw = bytes;
    for (size_t i = 0; i < items_.size(); ++i) {
      items_[i]->first(raw);
      raw += schema.items[i].size;
    }
  }

  void next(uint8_t* out, uint64_t n) override {
    if (n > points_ - done_) throw std::logic_error("laz: more records asked of a chunk than it holds");
    if (n == 0) return;
    if (done_ == 0) {
      std::memcpy(out, bytes_, schema_.record_length);
      out += schema_.record_length;
      ++done_, --n;
      if (points_ > 1) dec_.emplace(bytes_ + schema_.record_length, bytes_ + size_);
    }
    for (; n > 0; --n) {
      for (size_t i = 0; i < items_.size(); ++i) {
        items_[i]->next(*dec_, out);
        out += schema_.items[i].size;
      }
      if ((++done_ & 1023) == 0) check();
    }
    check();
  }

 private:
  // A sound stream never reads past its end (the encoder pads it for the decoder's reads ahead): reading past
  // it means the chunk was cut short or holds fewer points than it should.
  void check() const {
    if (dec_ && dec_->overrun() != 0)
      throw LazError("the chunk's " + n_of(size_) + " bytes end before its " + n_of(points_) + " points do (by point " +
                     n_of(done_) + ")");
  }

  const Schema& schema_;
  const uint8_t* bytes_;
  size_t size_;
  uint64_t points_, done_ = 0;
  std::vector<std::unique_ptr<PointwiseItem>> items_;
  std::optional<ArithmeticDecoder> dec_;
};

}  // namespace

std::unique_ptr<ChunkDecoder> open_pointwise_chunk(const Schema& schema, const uint8_t* bytes, size_t size,
                                                   uint64_t points) {
  return std::make_unique<PointwiseChunk>(schema, bytes, size, points);
}

}  // namespace mv::laz
