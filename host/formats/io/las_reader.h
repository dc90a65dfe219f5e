// LAS point reader: LAS 1.0-1.4, uncompressed or LAZ (io/laz_records.h), point data record formats 0, 1, 2,
// 3, 6, 7, 8.
//
// Positions are the records' raw int32 X, Y, Z; info().scale and offset are the header's (world = offset +
// scale * X, in double). Intensity is always delivered (kPointIntensity); formats 2, 3, 7 and 8 add RGB
// (kPointRgb, 16-bit as stored). A record longer than its format's fields carries "extra bytes": into
// PointColumns::extra with PointReadOptions::carry_extra_bytes (info().extra_bytes = the surplus, kPointExtra),
// else skipped. Other fields (returns, classification, GPS time, format 8's NIR) are skipped. info().crs is the
// OGC WKT record's text, else a summary of the GeoTIFF keys, else empty. z_up is true.
// The records are read in batches through a buffer of at most min(ram_bytes, 1 MiB) (at least one record).
// Internal to host/io (open_points chooses it); not a public API.
#pragma once
#include <memory>
#include <string>

#include "point_source.h"

namespace mv::io {

std::unique_ptr<PointSource> open_las(const std::string& path, const PointReadOptions& options);

}  // namespace mv::io
