// LAS and LAZ rewritten as plain LAS: the header, every variable-length record but LASzip's (and COPC's, which
// describe a compressed file's chunks), the point records
// decompressed (in file order, byte for byte as the LAS specification lays them out, every attribute of the
// point format and its extra bytes), then LAS 1.4's extended records, with the offsets that move (point data,
// extended records) and the point format's compression bits rewritten. The plain way to decompress LAZ, and
// what megavox's LAZ checks compare.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <functional>
#include <string>

namespace mv::io {

struct LasConvertReport {
  std::string input_format;  // "LAZ 1.2, point format 3 (LASzip 2.2, pointwise chunked, 3 chunks)"
  uint64_t points = 0;          // read (with bounds on a COPC file: in the chunks read)
  uint64_t points_written = 0;  // in the bounds, where given
  uint64_t chunks = 0, chunks_read = 0;  // LAZ: in the file, and read (fewer with bounds on a COPC file)
  uint32_t record_length = 0;
  uint64_t bytes_written = 0;
  double decode_seconds = 0;  // reading and decompressing the points, without writing them
};

// `output` must already be resolved (io/output_path.h); it is written atomically, so a failure leaves nothing.
// `threads` decode LAZ chunks at once (0: one per hardware thread). `progress(points done)` is called after
// each batch. With `bounds` (world min x, y, z, max x, y, z; both ends kept) only the points inside are written,
// and the header's counts and bounds say so; a COPC file decodes only the chunks whose node meets the box.
// Throws mv::Error naming the file and the fault.
LasConvertReport write_plain_las(const std::string& input, const std::string& output, unsigned threads,
                                 const std::function<void(uint64_t)>& progress = {},
                                 const std::optional<std::array<double, 6>>& bounds = {});

// Only decodes: every point of `input` read and decompressed into memory and dropped (the decoding benchmark).
LasConvertReport decode_las_points(const std::string& input, unsigned threads);

}  // namespace mv::io
