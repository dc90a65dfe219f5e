// megavox — the .mvx container: one encoded DAG with its grid, bounds and counts, or (version 2 on) one point
// cloud's LOD hierarchy.
//
// Little-endian. A 4 KiB header page: magic "MEGAVOX\x1a", version, encoding, levels, the world-to-grid
// transform (origin, voxel size, resolution), the content kind (version 2 on: 0 voxels, 1 points), the model's
// bounds, the voxel (or point) count, a table of up to 16 sections (kind, offset, bytes, XXH3-64 checksum) and
// the header's own XXH3-64. Sections start on 4 KiB boundaries (so a reader can mmap them).
// Voxels: counts (SVO and DAG nodes per level), level offsets (of the level-order stream), node words.
// Version 3 pages the nodes of every encoding: the nodes section holds the paged stream
// (paging/paged_stream.h for svo / svdag / ussvdag, paged_ssvdag.h for ssvdag: pages of page_words words, no node
// crossing a page, zero padding, pointers into the paged stream, the last page not padded), and a page index
// section (kind 14) holds page_words (a power of two, at least 16), the node order (0 level, 1 subtree), the
// page count, the paged stream's words, and one XXH3-64 per page over its page_words words (the last page
// zero-padded), so that a page read alone is checked; the nodes section's own checksum is 0 (unused) then.
// A paged ssvdag (always level order) adds a paged level starts section (kind 15): levels + 1 64-bit words,
// [1] the brick count and [3 .. L] where each inner level's first node lies in the stream, in 16-bit words.
// Points: a meta section (grid, cube, counts, attributes, CRS), nodes per level, the node table (breadth-first,
// 40 bytes per node) and one section per point column in node order, so the top levels' points are a prefix
// of every column: a reader can stop after the levels it wants.
// Version 4 adds voxel colours (kind 16, only in a file that has them): a 32-byte head (format 0 = raw RGB24,
// the quantization's bits, entries = every octree node, voxels and inner nodes) and the colours in depth-first order
// (docs/colour.md). Format 1 stores them palette-compressed (megavox/colour_palette.h; the head's two reserved
// words hold the blocks and palettes); the writer keeps raw where that is smaller.
// Version 5 makes a paged word stream (svo / svdag / ussvdag) in level order relative: each child pointer counts
// words from its child level's start, which a paged level starts section (kind 15) holds, levels + 1 64-bit
// words ([l] the first word of level l, [L] the root's 0, [0] 0), so each level reaches 2^32 words and the
// stream past them. In subtree order (pages mix levels) pointers stay absolute: the stream stays under 2^32 words,
// and the writer takes level order for a larger one. Versions 1 to 4 still open (their word pointers absolute);
// a file without colours and relative pointers is written as version 3 would be, bar the version number.
// Version 6 adds a point file's fields (kind 19, only where the cloud names them): a JSON array of {name, type,
// offset, count, scale, add, description}, what each point's extra bytes hold (megavox/points.h PointField).
// Versions 1 and 2 (unpaged voxels; version 2 points, the same sections as version 3's) still open.
// Written to a temporary name and renamed on success; the reader checks every field, every checksum and
// the encoding itself before returning.
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "megavox/colour_palette.h"
#include "megavox/encode.h"
#include "megavox/grid.h"
#include "megavox/points.h"

namespace mv {

inline constexpr uint32_t kMvxVersion = 6;
inline constexpr uint32_t kMvxPageWords = 4096;  // 16 KiB pages: the default of write_mvx

// How the nodes of a file are paged: pages of page_words words (a power of two, at least 16), nodes placed in
// `order` (an ssvdag: always level order). page_words 0: not paged (the level-order stream, resident only).
struct MvxPaging {
  uint32_t page_words = kMvxPageWords;
  NodeOrder order = NodeOrder::subtree;
};

// How write_mvx stores colours: the smaller of raw and palette (ties: raw), or one of them.
enum class ColourStorage { smallest, raw, palette };

// What a colour section holds (read_mvx fills the stored half; write_mvx returns all of it).
struct MvxColourStats {
  uint32_t format = 0;               // 0 raw RGB24, 1 palette
  uint64_t entries = 0, bytes = 0;   // colours stored; the section's bytes, head included (0: no colours)
  uint64_t blocks = 0, palettes = 0, palette_entries = 0, materials = 0;  // the palette's counts (0 when raw)
  // Write only: the palette's section bytes, also when raw was kept, and the time its selection took.
  uint64_t palette_bytes = 0;
  double palette_seconds = 0;
};

struct MvxFile {
  GridTransform grid;
  Bounds bounds;  // of the input model, in its own units
  uint64_t voxels = 0;
  std::vector<uint64_t> svo_nodes;  // index = level (0 = voxels)
  std::vector<uint64_t> dag_nodes;  // index = level (0 = voxels)
  // Voxel colours (version 4 on): RGB24 per octree node, voxels and inner nodes, in depth-first order
  // (docs/colour.md); empty for a colourless file.
  std::vector<uint8_t> colours;
  // read_mvx, for a palette-compressed colour section: the palette as stored (the colours above are its decode), so
  // a device can hold the colours compressed (kernels/common/trace_colour.h).
  std::shared_ptr<const ColourPalette> colour_palette;
  // The colours' quantization: at most 2^colour_bits distinct colours (24: as measured, lossless). Stored in the
  // colour section's head; for a palette the reader checks the distinct colours against it.
  uint32_t colour_bits = 24;
  ColourStorage colour_storage = ColourStorage::smallest;  // write_mvx only
  MvxColourStats colour_stats;                             // read_mvx only
  EncodedDag dag;  // read_mvx: always the level-order stream, whatever the file's paging
  // As read (write_mvx ignores these): the file's paging ({0} when not paged) and its paged stream's words.
  MvxPaging paging{0, NodeOrder::level};
  uint64_t paged_words = 0;
  bool size_plane = false;  // read_mvx: the paged file carries its colours' size plane (they stream with its pages)
};

enum class MvxContent { voxels, points };
// What a file holds, from its checked header alone.
MvxContent mvx_content(const std::string& path);

// Written paged as `paging` says (page_words 0: unpaged).
// Returns how the colours were stored (all zero without colours).
MvxColourStats write_mvx(const std::string& path, const MvxFile& file, const MvxPaging& paging = {});
// Voxel content; a point file is an error that says so. A paged file's pages are each checked against the page
// index and its stream turned back into level order (level_order_stream), checked on the way.
MvxFile read_mvx(const std::string& path);

void write_mvx_points(const std::string& path, const PointHierarchy& h);

// A point file whose points other processes hold in part (a build over MPI ranks): h has every node, but
// h.points only the points of the nodes `elsewhere` does not mark, in node order. At every level those nodes
// come before the marked ones, whose points `others` hands over: one column's bytes of the marked nodes of one
// level, in node order, through `put`.
enum class PointColumn { xyz, rgb, normal, intensity, extra };
using PutPointBytes = std::function<void(const void* data, size_t bytes)>;
struct PointsElsewhere {
  std::vector<bool> elsewhere;  // per node of h
  std::function<void(PointColumn column, uint32_t level, const PutPointBytes& put)> others;
};
void write_mvx_points(const std::string& path, const PointHierarchy& h, const PointsElsewhere& share);
// Checks every section and the hierarchy itself (codes, children, counts) before returning.
PointHierarchy read_mvx_points(const std::string& path);

std::string encoding_name(Encoding e);

}  // namespace mv
