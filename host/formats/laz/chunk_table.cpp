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

class TableReader {
 public:
  TableReader(std::FILE* file, const std::string& path, uint64_t size) : file_(file), path_(path), size_(size) {}

  [[noreturn]] void fail(const std::string& what) const { throw Error(path_ + ": " + what); }

  std::vector<uint8_t> bytes_at(uint64_t at, uint64_t n) const {
    std::vector<uint8_t> out(n);
    if (fseeko(file_, static_cast<off_t>(at), SEEK_SET) != 0)
      fail("cannot seek to byte " + num(at) + ": " + std::strerror(errno));
    if (io::read_some(file_, out.data(), n, path_) != n) fail("the file ended early, at byte " + num(at));
    return out;
  }

  int64_t i64_at(uint64_t at) const {
    const std::vector<uint8_t> b = bytes_at(at, 8);
    uint64_t v = 0;
    for (int i = 7; i >= 0; --i) v = (v << 8) | b[i];
    return static_cast<int64_t>(v);
  }

 private:
  std::FILE* file_;
  const std::string& path_;
  uint64_t size_;
};

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
  TableReader r(file, path, file_size);
  if (!schema.chunked()) {
    if (data_end <= point_offset) r.fail("the compressed point data is empty");
    if (points > 1 + kMaxPointsPerByte * (data_end - point_offset))
      r.fail("corrupt LAZ: " + num(points) + " points cannot be coded in " + num(data_end - point_offset) + " bytes");
    return {Chunk{point_offset, data_end - point_offset, points, 0}};
  }
  if (points == 0) return {};
  if (data_end < point_offset + 8) r.fail("the compressed point data has no room for its chunk table's position");
  int64_t table = r.i64_at(point_offset);
  if (table == -1 && file_size >= 8) table = r.i64_at(file_size - 8);  // written last by a writer that cannot seek
  if (table < static_cast<int64_t>(point_offset + 8) || static_cast<uint64_t>(table) + 8 > file_size)
    r.fail("corrupt LAZ: the chunk table position " + std::to_string(table) + " lies outside the file's point data (bytes " +
           num(point_offset + 8) + " to " + num(file_size) + ")");
  const std::vector<uint8_t> head = r.bytes_at(table, 8);
  const uint32_t version = head[0] | (head[1] << 8) | (head[2] << 16) | (static_cast<uint32_t>(head[3]) << 24);
  const uint32_t count = head[4] | (head[5] << 8) | (head[6] << 16) | (static_cast<uint32_t>(head[7]) << 24);
  if (version != 0) r.fail("corrupt LAZ: chunk table version " + num(version) + " (0 is defined)");
  const bool variable = schema.chunk_size == kVariableChunks;
  if (count == 0) r.fail("corrupt LAZ: the chunk table lists no chunks for " + num(points) + " points");
  if (!variable) {
    const uint64_t expected = (points + schema.chunk_size - 1) / schema.chunk_size;
    if (count != expected)
      r.fail("corrupt LAZ: the chunk table lists " + num(count) + " chunks; " + num(points) + " points in chunks of " +
             num(schema.chunk_size) + " make " + num(expected));
  } else if (count > points) {
    r.fail("corrupt LAZ: the chunk table lists " + num(count) + " chunks for " + num(points) + " points");
  }

  const uint64_t coded = std::min<uint64_t>(file_size - table - 8, kEntryBytes * count + 64);
  const std::vector<uint8_t> bytes = r.bytes_at(table + 8, coded);
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
        r.fail("corrupt LAZ: chunk " + num(i) + " of the chunk table holds " + num(c.points) + " points, but only " +
               num(points - first) + " of the header's " + num(points) + " remain");
      if (c.points > 1 + kMaxPointsPerByte * c.bytes)
        r.fail("corrupt LAZ: chunk " + num(i) + " claims " + num(c.points) + " points in " + num(c.bytes) +
               " bytes, more than LAZ can code in them");
      if (c.bytes > static_cast<uint64_t>(table) - at)
        r.fail("corrupt LAZ: chunk " + num(i) + " (" + num(c.bytes) + " bytes from byte " + num(at) +
               ") runs past the chunk table at byte " + num(table));
      at += c.bytes;
      first += c.points;
    }
    if (dec.overrun() != 0) r.fail("corrupt LAZ: the chunk table is cut short");
    if (first != points)
      r.fail("corrupt LAZ: the chunk table's chunks hold " + num(first) + " points, the header declares " + num(points));
  } catch (const LazError& e) {
    r.fail(std::string("corrupt LAZ chunk table: ") + e.what());
  }
  return chunks;
}

}  // namespace mv::laz
