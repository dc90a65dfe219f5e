// The attribute record the LAS reader gives each point (PointColumns::extra): every field of the point
// format beyond position, intensity and colour, decoded into one layout for all formats, then the record's
// extra bytes as stored, named and typed by the file's Extra Bytes records (LASF_Spec 4) where it has them.
//
//   u8 return_number, number_of_returns, classification, classification_flags (bit 0 synthetic, 1 key-point,
//   2 withheld, 3 overlap), scanner_channel, scan_direction_flag, edge_of_flight_line, user_data;
//   f32 scan_angle (degrees: a LAS 1.0-1.3 rank as is, LAS 1.4's 0.006-degree steps converted); u16
//   point_source_id; then f64 gps_time (formats 1, 3, 6, 7, 8), u16 nir (format 8), then the extra bytes.
//
// Internal to host/io (las_reader.cpp uses it); not a public API.
#pragma once
#include <cstdint>
#include <vector>

#include "megavox/points.h"

namespace mv::io::detail {

struct LasRecordLayout {
  std::vector<PointField> fields;
  uint32_t bytes = 0;     // the whole attribute record
  uint32_t standard = 0;  // its decoded fields, before the extra bytes
};

// The layout for point format `format` whose records carry `surplus` extra bytes described by `descriptors`
// (the Extra Bytes records' 192-byte entries, concatenated). Descriptors that do not fit the extra bytes, or
// have a type LAS does not define, leave the bytes they would cover unnamed ("extra_bytes", u8 x n).
LasRecordLayout las_record_layout(unsigned format, uint32_t surplus, const std::vector<uint8_t>& descriptors);

// Point `record` (a LAS record of `format`, `standard_length` bytes before its extra bytes) into its attribute
// record at `out` (layout.bytes bytes).
void las_attributes(unsigned format, uint32_t standard_length, const LasRecordLayout& layout,
                    const unsigned char* record, uint8_t* out);

}  // namespace mv::io::detail
