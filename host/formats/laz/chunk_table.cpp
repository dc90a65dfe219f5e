// The chunk table reader (chunk_table.h).
#include "chunk_table.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#include "io/file_ops.h"
#include "io/header_numbers.h"
#include "megavox/error.h"

namespace mv::laz {

namespace {

using io::detail::num;


// Bytes a coded table entry can take at most (two 32-bit corrections and their bucket symbols), with slack.
constexpr uint64_t kEntryBytes = 24;

// The most points a chunk's bytes can code. Every point after the first decodes at least four symbols of
// adaptive models whose likeliest symbol never passes 1 - 63/2^15 (the changed-fields mask, the x, y and z
// buckets), so a point costs at least 0.011 bits: at most 727 points a byte. A count above this bound is a
// lie, refused before any memory is sized by it.
constexpr uint64_t kMaxPointsPerByte = 1024;

}  // namespace

std::vector<Chunk> read_chunks(std::FILE* file, const std::string& path, uint64_t file_size, const Schema& schema,
                               uint64_t point_offset, uint64_t data_end, uint64_t points) {
  auto fail = [&](const std::string& what) { throw Error(path + ": " + what); };
  auto i64_at = [&](uint64_t at) {
    const std::vector<uint8_t> b = io::read_at(file, at, 8, path);
    uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | b[i];
    return static_cast<int64_t>(v);
  };
  if (!schema.chunked()) {
    if (data_end <= point_offset) fail("the compressed point data is empty");
    if (points > 1 + kMaxPointsPerByte * (data_end - point_offset))
      fail("corrupt LAZ: " + num(points) + " points cannot be coded in " + num(data_end - point_offset) + " bytes");
    return {Chunk{point_offset, data_end - point_offset, points, 0}};
  }
  if (points == 0) return {};
  if (data_end < point_offset + 8) fail("the compressed point data has no room for its chunk table's position");
  int64_t table = i64_at(point_offset);
  if (table == -1 && file_size >= 8) table = i64_at(file_size - 8);  // written last by a writer that cannot seek
  if (table < static_cast<int64_t>(point_offset + 8) || static_cast<uint64_t>(table) + 8 > file_size)
    fail("corrupt LAZ: the chunk table position " + std::to_string(table) + " lies outside the file's point data (bytes " +
           num(point_offset + 8) + " to " + num(file_size) + ")");
  const std::vector<uint8_t> head = io::read_at(file, table, 8, path);
  const uint32_t version = head[0] | (head[1] << 8) | (head[2] << 16) | (static_cast<uint32_t>(head[3]) << 24);
  const uint32_t count = head[4] | (head[5] << 8) | (head[6] << 16) | (static_cast<uint32_t>(head[7]) << 24);
  if (version != 0) fail("corrupt LAZ: chunk table version " + num(version) + " (0 is defined)");
  const bool variable = schema.chunk_size == kVariableChunks;
  if (count == 0) fail("corrupt LAZ: the chunk table lists no chunks for " + num(points) + " points");
  if (!variable) {
    const uint64_t expected = (points + schema.chunk_size - 1) / schema.chunk_size;
    if (count != expected)
      fail("corrupt LAZ: the chunk table lists " + num(count) + " chunks; " + num(points) + " points in chunks of " +
             num(schema.chunk_size) + " make " + num(expected));
  } else if (count > points) {
    fail("corrupt LAZ: the chunk table lists " + num(count) + " chunks for " + num(points) + " points");
  }

  const uint64_t coded = std::min<uint64_t>(file_size - table - 8, kEntryBytes * count + 64);
  const std::vector<uint8_t> bytes = io::read_at(file, table + 8, coded, path);
  std::vector<Chunk> chunks(count);
  try {
    ArithmeticDecoder dec(bytes.data(), bytes.data() + bytes.size());
    IntegerDecoder ic(32, 2);
    uint64_t at = point_offset + 8, first = 0;
    int32_t last_points = 0, last_bytes = 0;
    for (uint32_t i = 0; i < count; ++i) {
      Chunk& c = chunks[i];
      if (variable) {
        last_points = ic.decode(dec, last_points, 0);
        c.points = static_cast<uint32_t>(last_points);
      } else {
        c.points = std::min<uint64_t>(schema.chunk_size, points - first);
      }
      last_bytes = ic.decode(dec, last_bytes, 1);
      c.bytes = static_cast<uint32_t>(last_bytes);
      c.offset = at;
      c.first_point = first;
      if (c.points == 0 || c.points > points - first)
        fail("corrupt LAZ: chunk " + num(i) + " of the chunk table holds " + num(c.points) + " points, but only " +
               num(points - first) + " of the header's " + num(points) + " remain");
      if (c.points > 1 + kMaxPointsPerByte * c.bytes)
        fail("corrupt LAZ: chunk " + num(i) + " claims " + num(c.points) + " points in " + num(c.bytes) +
               " bytes, more than LAZ can code in them");
      if (c.bytes > static_cast<uint64_t>(table) - at)
        fail("corrupt LAZ: chunk " + num(i) + " (" + num(c.bytes) + " bytes from byte " + num(at) +
               ") runs past the chunk table at byte " + num(table));
      at += c.bytes;
      first += c.points;
    }
    if (dec.overrun() != 0) fail("corrupt LAZ: the chunk table is cut short");
    if (first != points)
      fail("corrupt LAZ: the chunk table's chunks hold " + num(first) + " points, the header declares " + num(points));
  } catch (const LazError& e) {
    fail(std::string("corrupt LAZ chunk table: ") + e.what());
  }
  return chunks;
}

}  // namespace mv::laz
