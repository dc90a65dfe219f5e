// The point records of a LAZ file, decompressed: the LASzip record read into a schema, the chunk table read,
// and the chunks decoded in batches, each chunk by one thread (chunks are independent), into plain LAS
// records that the LAS reader splits into columns as it does an uncompressed file's.
// Internal to host/io (las_reader.cpp uses it); not a public API.
#pragma once
#include <cstdint>
#include <array>
#include <cstdio>
#include <optional>
#include <memory>
#include <string>
#include <vector>

#include "las_header.h"
#include "laz/chunk_table.h"
#include "laz/copc_hierarchy.h"
#include "laz/laz_schema.h"

namespace mv::io {

class LazRecords {
 public:
  // `threads` decode at once (0: one per hardware thread); a batch holds at most `ram_bytes` of records (and
  // at most kMaxBatchBytes): a chunk larger than that is decoded on one thread a run at a time. Throws mv::Error naming `path` for a schema or chunk table no LAZ writer makes.
  // With `bounds` (world min x, y, z, max x, y, z) on a COPC file, only the chunks whose node cube meets the
  // box are read; records are not filtered here.
  LazRecords(std::FILE* file, const std::string& path, uint64_t file_size, const detail::LasHeader& header,
             unsigned threads, uint64_t ram_bytes, const std::optional<std::array<double, 6>>& bounds = {});

  // Up to `count` records into `out` (count * record length bytes); fewer only at the end of the points.
  // mv::Error naming the file and the chunk for data that does not decode.
  size_t read(uint8_t* out, size_t count);
  // Passes over whole chunks of at most `count` records in all, unread, where no chunk is part read; returns the
  // records passed over.
  uint64_t skip_chunks(uint64_t count);

  const laz::Schema& schema() const { return schema_; }
  size_t chunks() const { return chunks_.size(); }  // the chunks read
  size_t chunks_in_file() const { return chunks_in_file_; }
  uint64_t points() const { return points_; }       // in the chunks read
  bool copc() const { return copc_; }

 private:
  static constexpr uint64_t kMaxBatchBytes = 64ull << 20;

  void decode_batch();
  size_t batch_end(uint64_t room) const;
  uint64_t decode_chunks(size_t end, uint8_t* dest);
  void keep_chunks_meeting(const laz::CopcInfo& info, const std::array<double, 6>& box, uint64_t file_size);
  std::vector<uint8_t> chunk_bytes(size_t c);
  [[noreturn]] void chunk_failed(size_t c, const laz::LazError& e) const;

  std::FILE* file_;
  std::string path_;
  laz::Schema schema_;
  std::vector<laz::Chunk> chunks_;
  size_t chunks_in_file_ = 0;
  uint64_t points_ = 0;
  bool copc_ = false;
  unsigned threads_;
  uint64_t ram_bytes_;
  size_t next_chunk_ = 0;
  std::vector<uint8_t> ready_;  // decoded records not yet read
  size_t ready_at_ = 0;         // bytes of ready_ already read
  std::unique_ptr<laz::ChunkDecoder> big_;  // the chunk decoded a run at a time, with its bytes
  std::vector<uint8_t> big_bytes_;
  uint64_t big_left_ = 0;
};

}  // namespace mv::io
