// Streaming PLY 1.0 mesh reader (ascii, binary_little_endian, binary_big_endian).
//
// Vertices are read on construction, 12 bytes each, in RAM or, past a byte limit, in a memory-mapped scratch
// file the kernel pages to disk; faces are streamed in batches with next_triangles(). So a mesh larger than
// RAM can still be processed.
// Every fault -- missing file, malformed header, truncated data, bad index, non-finite coordinate, a
// count larger than the file could hold -- throws mv::Error naming the file and the fault. After an error
// from next_triangles the reader is spent: open the file again to retry.
//
// Accepted input:
// - one `vertex` element with scalar x, y, z of any type (converted to float), and red, green, blue when all
//   three are uchar or ushort; other properties skipped;
// - an optional `face` element after it whose list `vertex_indices` (or `vertex_index`) has integer count
//   and index types; polygons are fan-triangulated, a list with fewer than 3 indices is an error.
//   A file without a face element (a point cloud) is an empty mesh: info().faces == 0;
// - any other elements, before, between or after, are skipped (they must still be complete).
// Not accepted: a face element before the vertex element (faces could not be checked while streamed),
// more than 2^32 vertices (indices are 32-bit). Bytes after the last element are ignored.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace mv::io {

struct PlyInfo {
  uint64_t vertices = 0;
  uint64_t faces = 0;  // polygons as declared by the header (a quad becomes 2 triangles)
  std::string format;  // "ascii", "binary_little_endian" or "binary_big_endian"
  std::vector<std::string> comments;  // text after "comment ", in header order
};

class PlyMeshReader {
 public:
  // Opens `path`, parses the header and reads all vertices; positions over `ram_bytes` go to a scratch file
  // in $TMPDIR (or /tmp), mapped into memory.
  explicit PlyMeshReader(const std::string& path, uint64_t ram_bytes = UINT64_MAX, bool defer_vertices = false);
  ~PlyMeshReader();
  PlyMeshReader(PlyMeshReader&&) noexcept;
  PlyMeshReader& operator=(PlyMeshReader&&) noexcept;

  const PlyInfo& info() const;

  // x, y, z of every vertex, 3 floats per vertex.
  std::span<const float> positions() const;
  bool positions_mapped() const;  // in a scratch file (over ram_bytes)
  // Per vertex 0xBBGGRR when the vertices have red, green and blue as uchar or ushort (ushort: the high byte
  // unless every value fits 8 bits); empty otherwise.
  std::span<const uint32_t> colours() const;

  // Replaces `indices` with up to `max_triangles` triangles (3 vertex indices each) of the next faces; a
  // polygon may be split across calls. Returns false, with `indices` empty, once every face was read.
  bool next_triangles(std::vector<uint32_t>& indices, size_t max_triangles);

  // Before the first next_triangles: streams only faces [first, last), found by offset, which takes a binary
  // file whose faces are index lists alone and triangles (each face's count is checked to be 3 as it is read;
  // the first that is not fails). False, changing nothing, for any other layout. For a build over ranks.
  bool select_faces(uint64_t first, uint64_t last);
  // Bytes of the file that hold what this reader reads: the header, the elements before the faces and, with
  // select_faces, its faces only (with deferred vertices: the header, the vertices read and its faces).
  uint64_t bytes_spanned() const;

  // A build over ranks reading the vertices in shares: opened with defer_vertices, a binary file whose elements
  // before the faces all have fixed-size records skips its vertices (positions() and colours() stay empty) and
  // says so here; any other file reads them as usual.
  bool vertices_deferred() const;
  // Deferred vertices [first, last) read by offset: 3 floats each and, with colours, 3 channels each as stored
  // (colour_bits: 8 for uchar, 16 for ushort, 0 without), checked as reading them all checks them.
  void read_vertex_range(uint64_t first, uint64_t last, std::vector<float>& xyz, std::vector<uint16_t>& rgb);
  int colour_bits() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mv::io
