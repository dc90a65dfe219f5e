// A paged .mvx (version 3 on: any encoding with a page index) opened for streaming: the file
// is memory-mapped, never read whole; opening checks the header and the page index, and each page is checked
// against its hash when it is read. The page structure itself (pointers, nodes) is what `megavox info` and
// read_mvx check over all pages (level_order_stream).
#pragma once
#include <cstdint>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include "file_ops.h"
#include "megavox/colour_palette.h"
#include "megavox/encode.h"
#include "megavox/grid.h"

namespace mv {

class MvxPages {
 public:
  // Throws mv::Error for a file that is not a paged voxel .mvx: versions 1 and 2 and unpaged files say they
  // render resident; damage in the header, the page index or the paged level starts is named.
  explicit MvxPages(const std::string& path);
  // Whether `path` is a voxel .mvx with a page index (its header checked; throws mv::Error for a file that is
  // not a voxel .mvx or whose header is damaged).
  static bool is_paged(const std::string& path);
  MvxPages(const MvxPages&) = delete;
  MvxPages& operator=(const MvxPages&) = delete;

  const GridTransform& grid() const { return grid_; }
  const Bounds& bounds() const { return bounds_; }
  uint64_t voxels() const { return voxels_; }
  Encoding encoding() const { return encoding_; }
  uint32_t levels() const { return levels_; }
  NodeOrder order() const { return order_; }
  uint32_t page_words() const { return page_words_; }
  uint32_t pages() const { return static_cast<uint32_t>(hashes_.size()); }
  uint64_t words() const { return words_; }  // of the paged stream (the last page's padding not counted)
  const std::string& path() const { return path_; }
  // Where the levels start in the paged stream: an ssvdag's (PagedSsvdag::starts), a word stream's in level
  // order (version 5 on: its pointers count from them); empty where pointers are absolute words.
  const std::vector<uint64_t>& level_starts() const { return starts_; }
  // Whether the file has a voxel colour section, and (version 5 on) the size plane that lets a paged walk find a
  // hit's colour entry (paging/paged_sizes.h): plane_words() words a page, 0 without one.
  bool has_colours() const { return has_colours_; }
  uint32_t plane_words() const { return plane_words_; }
  // Colour entries (every octree node: the colour section's count).
  uint64_t colour_entries() const { return colour_entries_; }

  // Copies page `page` into `out` (page_words() words; the last page zero-padded) and checks its hash.
  // False with a message in *error on a page past the end, a wrong `out` size, a failed read (io::faults
  // kMappedRead) or a checksum mismatch; `out` then holds nothing to trust. Thread-safe.
  bool read_page(uint32_t page, std::span<uint32_t> out, std::string* error) const;
  // The same for page `page` of the size plane (plane_words() words).
  bool read_sizes(uint32_t page, std::span<uint32_t> out, std::string* error) const;
  // Entry e's colour, R | G << 8 | B << 16, read from the mapped colour section (a palette is parsed, and checked,
  // on the first call). Throws mv::Error for an entry past the colours or a damaged palette. Thread-safe.
  uint32_t colour(uint64_t e) const;

 private:
  // Page `page` of `per_page` words of the `total` words at file byte `offset`, checked against hashes[page].
  bool read_mapped(uint32_t page, std::span<uint32_t> out, std::string* error, uint64_t offset, uint64_t total,
                   uint32_t per_page, const std::vector<uint64_t>& hashes, const char* what) const;
  std::string path_;
  GridTransform grid_;
  Bounds bounds_;
  uint64_t voxels_ = 0;
  Encoding encoding_ = Encoding::svdag;
  uint32_t levels_ = 0;
  NodeOrder order_ = NodeOrder::subtree;
  uint32_t page_words_ = 0;
  uint64_t words_ = 0;
  std::vector<uint64_t> hashes_, size_hashes_;
  uint32_t plane_words_ = 0;
  uint64_t sizes_offset_ = 0;    // of the size plane in the file
  uint64_t colour_entries_ = 0, colours_offset_ = 0, colour_bytes_ = 0;  // the colour section (its head first)
  uint32_t colour_format_ = 0;      // its head's format (raw or palette), and the palette's counts
  uint64_t palette_counts_[2] = {0, 0};
  mutable std::once_flag palette_once_;
  mutable std::shared_ptr<const ColourPalette> palette_;  // a palette-compressed section, parsed
  std::vector<uint64_t> starts_;
  bool has_colours_ = false;
  io::MappedFile map_;                  // the whole file, read-only
  uint64_t nodes_offset_ = 0;           // of the nodes section in the file
};

}  // namespace mv
