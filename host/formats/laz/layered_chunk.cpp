// One chunk of LAZ's layered compressor (LASzip compressor 3, LAS 1.4 point formats 6-10), decoded into LAS
// point records. A chunk is stored as
//   the first point's record, raw;
//   uint32 the chunk's point count;
//   uint32 byte counts of every layer: item by item, in the schema's order, each item's layers in its order;
//   every layer's bytes, in the same order.
// Each layer is its own arithmetic-coded stream; an empty one means that field is the same in every point of
// the chunk. POINT14 comes first: it picks the context of the record's other items for each point
// (point14_item.h says how).
//
// Items: POINT14 (version 3, LASzip's prototype number 2 for the same coder, and 4, which differs only in the
// context it hands on), RGB14, RGBNIR14 and BYTE14 (versions 3 and 2; their version 4 decodes differently and
// is refused). Wave packets are not read.
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "laz_schema.h"
#include "layered_items.h"
#include "point14_item.h"

namespace mv::laz {

namespace {

const char* layered_item_name(ItemType type) {
  switch (type) {
    case ItemType::point14: return "POINT14";
    case ItemType::rgb14: return "RGB14";
    case ItemType::rgbnir14: return "RGBNIR14";
    case ItemType::byte14: return "BYTE14";
    case ItemType::wavepacket14: return "WAVEPACKET14";
    default: return "a pre-LAS 1.4 item";
  }
}

// How many layers `item` is stored in; throws for an item the layered decoder does not read.
size_t layered_item_layers(const Item& item, size_t index) {
  const std::string where = std::string(layered_item_name(item.type)) + " (item " + std::to_string(index) + ")";
  const bool v3 = item.version == 2 || item.version == 3;
  switch (item.type) {
    case ItemType::point14:
      if (index != 0) throw LazError("layered LAZ: " + where + " must be the first item and only once");
      if (!v3 && item.version != 4)
        throw LazError("layered LAZ: " + where + " version " + std::to_string(item.version) + " is unknown");
      if (item.size != Point14Decoder::kRecordBytes) break;
      return Point14Decoder::kLayers;
    case ItemType::rgb14:
    case ItemType::rgbnir14:
    case ItemType::byte14:
      if (index == 0) throw LazError("layered LAZ: the first item is " + where + ", not POINT14");
      if (item.version == 4)
        throw LazError("layered LAZ: " + where + " version 4 is not supported (it decodes unlike version 3)");
      if (!v3)
        throw LazError("layered LAZ: " + where + " version " + std::to_string(item.version) + " is unknown");
      if (item.type == ItemType::rgb14 && item.size == 6) return ColourDecoder::layers(false);
      if (item.type == ItemType::rgbnir14 && item.size == 8) return ColourDecoder::layers(true);
      if (item.type == ItemType::byte14 && item.size != 0) return item.size;
      break;
    default:
      throw LazError("layered LAZ: " + where + " is not supported by the layered decoder");
  }
  throw LazError("layered LAZ: " + where + " has an impossible size of " + std::to_string(item.size) + " bytes");
}

uint32_t layered_load_u32(const uint8_t* p) {
  return uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
}

// An item after POINT14: where its bytes go in the record and its decoder.
struct LayeredExtra {
  size_t offset;
  std::unique_ptr<ColourDecoder> colour;
  std::unique_ptr<Byte14Decoder> bytes;
};

}  // namespace

namespace {

class LayeredChunk final : public ChunkDecoder {
 public:
  LayeredChunk(const Schema& schema, const uint8_t* bytes, size_t size, uint64_t points)
      : bytes_(bytes), points_(points) {
    if (!schema.layered()) throw LazError("layered LAZ: the schema is not of the layered compressor");
    if (schema.items.empty()) throw LazError("layered LAZ: the schema lists no items");
    if (points == 0) throw LazError("layered LAZ: a chunk of no points");
    std::vector<size_t> layer_counts(schema.items.size());
    size_t total_layers = 0;
    uint64_t record = 0;
    for (size_t i = 0; i < schema.items.size(); ++i) {
      layer_counts[i] = layered_item_layers(schema.items[i], i);
      total_layers += layer_counts[i];
      record += schema.items[i].size;
    }
    if (record != schema.record_length)
      throw LazError("layered LAZ: the items make " + std::to_string(record) + "-byte records, the schema says " +
                     std::to_string(schema.record_length));
    record_ = record;

    // The raw first point, the point count and the layer sizes.
    const std::string truncated = "truncated chunk: " + std::to_string(size) + " bytes ";
    if (size < record) throw LazError(truncated + "hold no first point of " + std::to_string(record) + " bytes");
    size_t at = record;
    if (size - at < 4) throw LazError(truncated + "end before the chunk's point count");
    const uint32_t count = layered_load_u32(bytes + at);
    at += 4;
    if (count != points)
      throw LazError("the chunk holds " + std::to_string(count) + " points where the chunk table says " +
                     std::to_string(points));
    if ((size - at) / 4 < total_layers)
      throw LazError(truncated + "end within the sizes of the chunk's " + std::to_string(total_layers) + " layers");
    layers_.resize(total_layers);
    size_t data = at + 4 * total_layers;
    for (size_t l = 0; l < total_layers; ++l) {
      const uint32_t n = layered_load_u32(bytes + at + 4 * l);
      if (n > size - data)
        throw LazError(truncated + "end within layer " + std::to_string(l) + " (" + std::to_string(n) +
                       " bytes declared at offset " + std::to_string(data) + ")");
      layers_[l] = LayerBytes{bytes + data, bytes + data + n};
      data += n;
    }
    if (points == 1) return;  // nothing coded to read

    point_ = std::make_unique<Point14Decoder>(bytes, layers_.data(), schema.items[0].version);
    extras_.reserve(schema.items.size() - 1);
    size_t offset = schema.items[0].size, first_layer = layer_counts[0];
    for (size_t i = 1; i < schema.items.size(); ++i) {
      const Item& item = schema.items[i];
      const unsigned context = point_->items_context();
      LayeredExtra e{offset, nullptr, nullptr};
      if (item.type == ItemType::byte14)
        e.bytes = std::make_unique<Byte14Decoder>(bytes + offset, context, item.size, &layers_[first_layer]);
      else
        e.colour = std::make_unique<ColourDecoder>(bytes + offset, context, item.type == ItemType::rgbnir14,
                                                   &layers_[first_layer]);
      extras_.push_back(std::move(e));
      offset += item.size;
      first_layer += layer_counts[i];
    }
  }

  void next(uint8_t* out, uint64_t n) override {
    if (n > points_ - done_) throw std::logic_error("laz: more records asked of a chunk than it holds");
    if (n == 0) return;
    if (done_ == 0) {
      std::memcpy(out, bytes_, record_);
      out += record_;
      ++done_, --n;
    }
    for (; n > 0; --n, out += record_) {
      point_->next(out);
      const unsigned context = point_->items_context();
      for (LayeredExtra& e : extras_) {
        if (e.colour) e.colour->next(context, out + e.offset);
        else e.bytes->next(context, out + e.offset);
      }
      if ((++done_ & 1023) == 0) check_overrun();
    }
    check_overrun();
  }

 private:
  // A sound chunk never reads past the end of a layer; corrupt ones are cut short rather than decoded to the end.
  void check_overrun() const {
    if (!point_) return;
    size_t overrun = point_->overrun();
    for (const LayeredExtra& e : extras_) overrun += e.colour ? e.colour->overrun() : e.bytes->overrun();
    if (overrun != 0)
      throw LazError("truncated chunk: its layers end before its " + std::to_string(points_) + " points do (" +
                     std::to_string(overrun) + " bytes missing by point " + std::to_string(done_) + ")");
  }

  const uint8_t* bytes_;
  uint64_t points_, done_ = 0, record_ = 0;
  std::vector<LayerBytes> layers_;
  std::unique_ptr<Point14Decoder> point_;
  std::vector<LayeredExtra> extras_;
};

}  // namespace

std::unique_ptr<ChunkDecoder> open_layered_chunk(const Schema& schema, const uint8_t* bytes, size_t size,
                                                 uint64_t points) {
  return std::make_unique<LayeredChunk>(schema, bytes, size, points);
}

}  // namespace mv::laz
