// What a LAZ file declares about its compression: the LASzip record (VLR "laszip encoded" 22204) read into a
// schema -- compressor, chunk size and the item list that composes each point record -- and the chunk
// decoders that turn one chunk's bytes into plain LAS point records.
//
// A LAS point record is the concatenation of its items in the order listed (POINT10 + GPSTIME11 + RGB12 +
// BYTE for format 3 with extra bytes, POINT14 + RGB14 + BYTE14 for format 7 ...). Chunks are independent:
// each restarts every model, so they decode in parallel.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "arithmetic_decoder.h"

namespace mv::laz {

// LASzip item types (the LAZ specification's numbering).
enum class ItemType : uint16_t {
  byte10 = 0,  // extra bytes, LAS 1.0-1.3 point formats
  point10 = 6,
  gpstime11 = 7,
  rgb12 = 8,
  wavepacket13 = 9,
  point14 = 10,
  rgb14 = 11,
  rgbnir14 = 12,
  wavepacket14 = 13,
  byte14 = 14,  // extra bytes, LAS 1.4 point formats 6-10
};

struct Item {
  ItemType type;
  uint16_t size;     // bytes of the record it fills
  uint16_t version;  // the item coder's version: 1 and 2 for pointwise items, 3 (and 4) for layered ones
};

enum class Compressor : uint16_t { none = 0, pointwise = 1, pointwise_chunked = 2, layered_chunked = 3 };

struct Schema {
  Compressor compressor = Compressor::none;
  uint16_t coder = 0;  // 0: arithmetic, the only coder LASzip defines
  uint8_t version_major = 0, version_minor = 0;
  uint16_t version_revision = 0;
  uint32_t options = 0;
  uint32_t chunk_size = 0;  // points per chunk; kVariableChunks: each chunk's count is in the chunk table
  std::vector<Item> items;
  uint32_t record_length = 0;  // the sum of the items' sizes

  bool layered() const { return compressor == Compressor::layered_chunked; }
  bool chunked() const { return compressor != Compressor::pointwise; }
};

inline constexpr uint32_t kVariableChunks = 0xFFFFFFFFu;

// Reads the LASzip record's `size` bytes and checks it against the LAS header's point format (without the
// compression bits) and record length. Throws LazError naming the fault: an unknown compressor or coder, an
// item of unknown type or version, an item list that does not compose the point format's record.
Schema parse_schema(const uint8_t* bytes, size_t size, unsigned point_format, uint32_t record_length);

// One chunk being decoded: its compressed bytes (which the caller keeps alive) turned into `points` LAS records
// of schema.record_length bytes, a run at a time, so a chunk of any size decodes through a bounded buffer.
// Throws LazError when the bytes end before the points do or hold what no encoder writes.
class ChunkDecoder {
 public:
  virtual ~ChunkDecoder() = default;
  // The chunk's next `n` records (n at most the points left) into `out`.
  virtual void next(uint8_t* out, uint64_t n) = 0;
};

std::unique_ptr<ChunkDecoder> open_pointwise_chunk(const Schema& schema, const uint8_t* bytes, size_t size,
                                                   uint64_t points);
std::unique_ptr<ChunkDecoder> open_layered_chunk(const Schema& schema, const uint8_t* bytes, size_t size,
                                                 uint64_t points);

inline std::unique_ptr<ChunkDecoder> open_chunk(const Schema& schema, const uint8_t* bytes, size_t size,
                                                uint64_t points) {
  return schema.layered() ? open_layered_chunk(schema, bytes, size, points)
                          : open_pointwise_chunk(schema, bytes, size, points);
}

// A whole chunk at once.
inline void decode_chunk(const Schema& schema, const uint8_t* bytes, size_t size, uint64_t points, uint8_t* out) {
  if (points != 0) open_chunk(schema, bytes, size, points)->next(out, points);
}

}  // namespace mv::laz
