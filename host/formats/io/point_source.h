// Point clouds from a file, read as a stream: the header on opening, then the points in batches, so a cloud
// larger than RAM passes through a bounded buffer.
//
// Formats, chosen by content:
// - LAS 1.0 to 1.4, point data record formats 0 to 10, and LAZ formats 0, 1, 2, 3, 6, 7, 8 (io/las_reader.h):
//   the raw int32 X, Y, Z with the header's scale and offset; intensity, RGB (formats 2, 3, 5, 7, 8, 10) and the record's
//   extra bytes; the CRS from the WKT or GeoTIFF-key records. LAZ is decompressed by megavox's own decoder
//   (host/formats/laz), its chunks in parallel.
// - PLY 1.0, ascii or binary (io/ply_points.h): the `vertex` element's x, y, z on a grid chosen from the data's
//   precision (the rule is in ply_points.h), with optional RGB, normals and intensity.
//
// Every fault -- a missing file, a malformed header, truncated data, a count larger than the file could hold,
// a non-finite coordinate -- throws mv::Error naming the file and the fault. After an error from next() the
// source is spent: open the file again to retry.
#pragma once
#include <cstddef>
#include <cstdint>
#include <array>
#include <memory>
#include <functional>
#include <optional>
#include <string>

#include "megavox/points.h"

namespace mv::io {

class PointSource {
 public:
  virtual ~PointSource() = default;
  virtual const PointCloudInfo& info() const = 0;
  // Appends up to max_points (at least 1) points to `out` (the columns info().attributes names); false,
  // appending nothing, once every point was read.
  virtual bool next(PointColumns& out, size_t max_points) = 0;
  // The file's point records next() went through so far: the points it delivered, and with a --bounds box
  // (LAS, LAZ) those it tested and left out too. info().points in all.
  virtual uint64_t records_read() const = 0;
  // Passes over the next n records (a build over ranks reads its slice of the file; a box's test is not made on
  // them); past the end it stops there. Returns how many it passed over unread: all where it seeks
  // (uncompressed LAS, binary PLY of fixed-size records), LAZ's whole chunks, none where it reads them.
  virtual uint64_t skip(uint64_t n);
  // Whether opening it read the whole file (a PLY's grid pass, where it cannot seek to PointReadOptions' slice).
  virtual bool read_whole_file() const { return false; }
};

struct PointReadOptions {
  bool carry_extra_bytes = true;    // LAS: the record's bytes past its format's fields, into PointColumns::extra
  // LAS: the most its read buffer holds (and at most 1 MiB, at least one record); PLY reads through a fixed
  // 1 MiB block buffer. No reader holds a whole cloud.
  uint64_t ram_bytes = UINT64_MAX;
  // LAZ: threads decoding chunks at once (0: one per hardware thread).
  unsigned threads = 0;
  // LAS and LAZ: only the points inside this box (world units: min x, y, z, then max x, y, z; both ends kept);
  // a COPC file decodes only the chunks whose octree node meets it. Unset: every point. info().points is then
  // the count of the points read before the test (the chunks decoded), which next() may deliver fewer of.
  std::optional<std::array<double, 6>> bounds;
  // PLY, a build over ranks: the grid's first pass covers only the slice of the N records that rank `part` of
  // `parts` reads, [N part / parts, N (part + 1) / parts), where the file lets the reader seek to it (binary,
  // fixed-size records after elements of fixed-size records; else the whole file), and `agree_extent` turns
  // its largest |coordinate| into the one every rank's grid is made from.
  int slice_part = 0, slice_parts = 1;
  std::function<double(double)> agree_extent;
};

// Opens `path` by its content: "ply\n" is PLY, "LASF" is LAS or LAZ. Anything else throws mv::Error naming
// the file and the formats accepted.
std::unique_ptr<PointSource> open_points(const std::string& path, const PointReadOptions& options = {});

}  // namespace mv::io
