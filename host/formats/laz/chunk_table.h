// Where a LAZ file's chunks lie: the chunk table a chunked compressor writes after the point data (its position
// is the int64 that opens the point data, or, where the writer could not seek back, the file's last 8 bytes),
// holding each chunk's compressed bytes and, for variable chunks, its points, coded with the integer corrector.
// The pointwise compressor has no chunks: its point data is one chunk.
#pragma once
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "laz_schema.h"

namespace mv::laz {

struct Chunk {
  uint64_t offset = 0;  // in the file
  uint64_t bytes = 0;
  uint64_t points = 0;
  uint64_t first_point = 0;  // the index of its first point in the file
};

// The chunks of the point data that starts at `point_offset` and must end by `data_end` (the extended
// records or the end of the file), holding `points` points. Every chunk is checked to lie in the point data
// and the counts to add up to `points`. Throws mv::Error naming `path` and the fault.
std::vector<Chunk> read_chunks(std::FILE* file, const std::string& path, uint64_t file_size, const Schema& schema,
                               uint64_t point_offset, uint64_t data_end, uint64_t points);

}  // namespace mv::laz
