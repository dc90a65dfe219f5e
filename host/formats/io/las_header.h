// LAS header: the public header block, the variable-length records (and a LAS 1.4 file's extended ones) and
// the CRS they declare, read and checked against the ASPRS LAS 1.0-1.4 specification. Internal to host/io
// (used by the LAS reader); not a public API.
#pragma once
#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace mv::io::detail {

// A little-endian value of the file (LAS is little-endian throughout).
template <class T>
T le(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1) {
    auto u = std::bit_cast<
        std::conditional_t<sizeof(T) == 2, uint16_t, std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>>(v);
    if constexpr (sizeof(T) == 2) u = __builtin_bswap16(u);
    if constexpr (sizeof(T) == 4) u = __builtin_bswap32(u);
    if constexpr (sizeof(T) == 8) u = __builtin_bswap64(u);
    v = std::bit_cast<T>(u);
  }
  return v;
}

// Bytes of a record of point data format `format` without extra bytes; 0 for a format the reader refuses.
uint32_t las_standard_record_length(unsigned format);

// Where a point format keeps its fields (bytes into the record); rgb 0 when it has none.
uint32_t las_rgb_offset(unsigned format);

struct LasHeader {
  uint8_t version_major = 0, version_minor = 0;
  uint16_t header_size = 0;
  uint32_t point_offset = 0;  // "offset to point data"
  uint32_t vlr_count = 0;
  uint8_t point_format = 0;  // without the compression bits
  uint16_t record_length = 0;
  uint32_t legacy_points = 0;
  uint64_t points64 = 0;  // LAS 1.4's 64-bit count (0 before 1.4)
  uint64_t points = 0;    // the count that applies
  double scale[3] = {1, 1, 1};
  double offset[3] = {0, 0, 0};
  double min[3] = {0, 0, 0}, max[3] = {0, 0, 0};
  uint64_t waveform_start = 0;   // LAS 1.3+
  uint64_t evlr_start = 0;       // LAS 1.4
  uint32_t evlr_count = 0;       // LAS 1.4
  uint32_t standard_length = 0;  // of point_format's fields; record_length - standard_length are extra bytes
  std::string crs;               // OGC WKT, or a summary of the GeoTIFF keys, or empty
  bool compressed = false;       // LAZ: the point format's compression bit is set
  std::vector<uint8_t> laszip;   // the LASzip record's bytes (VLR "laszip encoded" 22204); LAZ only
  std::vector<uint8_t> copc;     // COPC's info record (VLR "copc" 1), where the file is COPC
  std::vector<uint8_t> extra_bytes_descriptors;  // every Extra Bytes record's (LASF_Spec 4) 192-byte entries
};

// Reads and checks the header and its records from `file` (of `file_size` bytes). Throws mv::Error naming
// `path` and the fault: not LAS, a truncated or inconsistent header, an unsupported version or point format,
// records that overrun, a point count larger than the file holds (uncompressed), a compressed file without
// its LASzip record.
LasHeader read_las_header(std::FILE* file, const std::string& path, uint64_t file_size);

}  // namespace mv::io::detail
