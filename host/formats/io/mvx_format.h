// The .mvx container's shared layout (include/megavox/mvx.h): the header page, the section table and the
// checked reads and atomic writes every content kind uses. Internal to host/io.
#pragma once
#include <xxhash.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "file_ops.h"
#include "megavox/error.h"

namespace mv::mvx_format {

constexpr char kMagic[8] = {'M', 'E', 'G', 'A', 'V', 'O', 'X', '\x1a'};
constexpr uint64_t kPage = 4096;
constexpr uint32_t kMaxSections = 16;
// Voxel content (version 4 on: voxel colours, kind 16): counts, levels, nodes (or inner + bricks), the page index
// of paged nodes (version 3), and where the levels start in the paged stream: a paged ssvdag's
// (PagedSsvdag::starts), and from version 5 on a word stream's in level order (its pointers count from them).
// Point content (version 2 on): the rest. Kinds are shared by both contents: a new one takes the next number.
enum SectionKind : uint32_t {
  kCounts = 1, kLevels = 2, kNodes = 3, kInner = 4, kBricks = 5,
  kSecPointMeta = 6, kSecPointNodes = 7, kSecPointXyz = 8, kSecPointRgb = 9, kSecPointNormal = 10,
  kSecPointIntensity = 11, kSecPointExtra = 12, kSecPointLevels = 13, kPageIndex = 14, kPagedStarts = 15,
  kColours = 16, kSizeIndex = 17, kSizes = 18, kSecPointFields = 19,
};
constexpr uint32_t kKinds = 20;

// The size plane of a paged file with colours (version 5 on; paging/paged_sizes.h): the size index (kind 17: this
// head, then one XXH3-64 per page over its plane_words words, the last page zero-padded) and the plane itself
// (kind 18, checked page by page), page for page beside the nodes.
struct SizeIndexHead {
  uint32_t plane_words, reserved;  // plane words per page: page_words times size_plane_words(encoding)
  uint64_t pages;
};
static_assert(sizeof(SizeIndexHead) == 16);

// The voxel colours section (version 4 on): this head, then `entries` colours of `bits` bits in depth-first
// order; `bits`: the quantization (at most 2^bits distinct colours; 24 lossless), entries stay RGB24 either way.
// Format 0 is raw RGB24 (3 bytes per entry, R first), `counts` zero. Format 1 is palette-compressed
// (megavox/colour_palette.h: palette_serialise's bytes follow), `counts` = blocks, palettes.
struct ColourHead {
  uint32_t format, bits;
  uint64_t entries;
  uint64_t counts[2];
};
static_assert(sizeof(ColourHead) == 32);
enum ColourFormat : uint32_t { kColourRaw24 = 0, kColourPalette24 = 1 };
// Header::content (version 2; version 1 files are voxels and hold 0 there).
enum Content : uint32_t { kVoxels = 0, kPoints = 1 };

struct Section {
  uint32_t kind = 0, reserved = 0;
  uint64_t offset = 0, bytes = 0, checksum = 0;
};

struct Header {
  char magic[8];
  uint32_t version, encoding, levels, sections;
  double origin[3], voxel_size;
  uint32_t resolution, content;
  double bounds_lo[3], bounds_hi[3];
  uint64_t voxels;  // points: the points kept
  Section table[kMaxSections];
  uint64_t checksum;  // XXH3-64 of the bytes above
};
static_assert(sizeof(Header) < kPage);

// The page index section: this head, then one XXH3-64 per page (over page_words words, the last page
// zero-padded).
struct PageIndexHead {
  uint32_t page_words, order;  // order: NodeOrder
  uint64_t pages, words;       // words: of the paged stream (the nodes section holds words * 4 bytes)
};
static_assert(sizeof(PageIndexHead) == 24);
constexpr uint32_t kMinPageWords = 16;        // the smallest power of two that holds a node of 9 words
constexpr uint32_t kMaxPageWords = 1u << 24;  // 64 MiB

// The page index of a version 3 voxel file, as read_page_index checked it.
struct PageIndex {
  PageIndexHead head{};
  std::vector<uint64_t> hashes;
};

// The hash a page's page_words words must have; `words` may be shorter (the last page): zeros follow.
uint64_t page_hash(const uint32_t* words, uint64_t count, uint32_t page_words);

inline uint64_t hash(const void* data, size_t bytes) { return XXH3_64bits(data, bytes); }

struct Blob {
  uint32_t kind;
  const void* data;
  uint64_t bytes;
  bool checked = true;  // false: checksum 0 (paged nodes: the page index checks each page)
};

// Fills h's magic, section table and checksum from `blobs` (each on its own 4 KiB pages after the header page)
// and writes the file through a temporary name.
void write_file(const std::string& path, Header& h, const std::vector<Blob>& blobs);

// A section whose bytes come in pieces (a point file whose points other processes hold): its size, known
// before, and `write`, which hands every piece to `put`, in order.
using PutBytes = std::function<void(const void* data, size_t bytes)>;
struct StreamedBlob {
  uint32_t kind;
  uint64_t bytes;
  std::function<void(const PutBytes& put)> write;
  bool checked = true;
};
// The same file as write_file writes from those sections, hashed as they pass; the header page goes last.
void write_file(const std::string& path, Header& h, const std::vector<StreamedBlob>& blobs);

// An opened file whose header, checksum, section table and total size were checked; versions 1 to 3.
struct Opened {
  io::FilePtr file{nullptr, &std::fclose};
  Header header{};
  const Section* find[kKinds] = {};  // the section of each kind, or null
};
Opened open_file(const std::string& path);

// The header and section table of a voxel file (encoding, levels, grid, which sections): mv::Error otherwise.
void check_voxel_file(const Opened& o, const std::string& path);

// The paged level starts (levels + 1 of them), read and checksummed; their order and the stream they describe
// are checked where they are used (ssvdag_from_pages, level_order_stream, MvxPages).
std::vector<uint64_t> read_paged_starts(const Opened& o, const std::string& path);
// Those of a paged file, as its encoding, node order and version say it has them (a paged ssvdag: always; a
// word stream in level order: from version 5 on, its pointers counting from them), or none (absolute word
// pointers). mv::Error where the file holds starts it should not or lacks them.
std::vector<uint64_t> paged_level_starts(const Opened& o, const PageIndex& pi, const std::string& path);

// The size index of a paged file with colours (version 5 on), checked against its page index: the page count, the
// plane's words per page, the plane section's size. An empty index when the file has none (older versions).
struct SizeIndex {
  SizeIndexHead head{};
  std::vector<uint64_t> hashes;
};
SizeIndex read_size_index(const Opened& o, const PageIndex& pi, const std::string& path);

// The page index of an opened file with both its nodes and page index sections, checked: its checksum,
// page_words, the counts against the nodes section's size. mv::Error naming the fault.
PageIndex read_page_index(const Opened& o, const std::string& path);

// Section `s` read whole, its size and checksum checked.
// `checked` false: the checksum is not looked at (paged nodes, whose pages the caller checks).
template <class T>
std::vector<T> section_data(std::FILE* f, const Section& s, const std::string& path, const char* what,
                            bool checked = true) {
  if (s.bytes % sizeof(T)) throw Error(path + ": " + what + " section has a partial element");
  std::vector<T> v(s.bytes / sizeof(T));
  if (std::fseek(f, static_cast<long>(s.offset), SEEK_SET) != 0 || io::read_some(f, v.data(), s.bytes, path) != s.bytes)
    throw Error(path + ": truncated: the " + what + " section ends past the end of the file");
  if (checked && hash(v.data(), s.bytes) != s.checksum)
    throw Error(path + ": checksum mismatch in the " + what + " section");
  return v;
}

}  // namespace mv::mvx_format
