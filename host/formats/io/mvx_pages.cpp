#include "mvx_pages.h"


#include <algorithm>
#include <array>
#include <cstdint>
#include <cerrno>
#include <cstring>

#include "file_ops.h"
#include "megavox/error.h"
#include "megavox/mvx.h"
#include "mvx_format.h"

namespace mv {

using namespace mvx_format;

MvxPages::MvxPages(const std::string& path) : path_(path) {
  PageIndex pi;
  uint64_t file_bytes = 0;
  {
    const Opened o = open_file(path);  // the header page alone, read through stdio
    check_voxel_file(o, path);
    const Header& h = o.header;
    if (!o.find[kPageIndex])
      throw Error(path + ": not paged (.mvx version " + std::to_string(h.version) +
                  ", no page index): it renders resident, without a page cache (or rebuild it with this megavox)");
    pi = read_page_index(o, path);
    starts_ = paged_level_starts(o, pi, path);
    // What the traversal reads of them: in order, inside the stream (ssvdag_from_pages and level_order_stream
    // check the rest). An ssvdag's count 16-bit words (bricks from 0); a word stream's words, root level first,
    // each level under 2^32 words (its pointers' reach).
    const uint32_t L = h.levels;
    bool ok = true;
    if (h.encoding == static_cast<uint32_t>(Encoding::ssvdag)) {
      ok = starts_[0] == 0 && starts_[2] == 0 && starts_[1] * 4 <= starts_[3];
      for (uint32_t l = 4; l <= L; ++l) ok = ok && starts_[l] > starts_[l - 1];
      ok = ok && (pi.head.words == 0 || starts_[L] < 2 * pi.head.words);
    } else if (!starts_.empty()) {
      ok = starts_[0] == 0 && starts_[L] == 0;
      for (uint32_t l = L; ok && l >= 1; --l) {
        const uint64_t end = l == 1 ? pi.head.words : starts_[l - 1];
        ok = starts_[l] < end;
      }
    }
    if (!ok) throw Error(path + ": bad paged level starts");
    encoding_ = static_cast<Encoding>(h.encoding);
    levels_ = h.levels;
    grid_.resolution = h.resolution;
    grid_.voxel_size = h.voxel_size;
    for (int a = 0; a < 3; ++a) {
      grid_.origin[a] = h.origin[a];
      bounds_.lo[a] = h.bounds_lo[a];
      bounds_.hi[a] = h.bounds_hi[a];
    }
    voxels_ = h.voxels;
    has_colours_ = o.find[kColours] != nullptr;
    const SizeIndex si = read_size_index(o, pi, path);
    plane_words_ = si.head.plane_words;
    size_hashes_ = si.hashes;
    if (o.find[kSizes]) sizes_offset_ = o.find[kSizes]->offset;
    if (has_colours_) {
      ColourHead head{};
      const Section& s = *o.find[kColours];
      if (s.bytes < sizeof head || std::fseek(o.file.get(), static_cast<long>(s.offset), SEEK_SET) != 0 ||
          std::fread(&head, sizeof head, 1, o.file.get()) != 1)
        throw Error(path + ": the colours section is shorter than its head");
      if ((head.format != kColourRaw24 && head.format != kColourPalette24) ||
          (head.format == kColourRaw24 && s.bytes - sizeof head != head.entries * 3))
        throw Error(path + ": colours of unknown format " + std::to_string(head.format) + " or size");
      colour_entries_ = head.entries;
      colour_format_ = head.format;
      palette_counts_[0] = head.counts[0];
      palette_counts_[1] = head.counts[1];
      colours_offset_ = s.offset;
      colour_bytes_ = s.bytes;
    }
    nodes_offset_ = o.find[kNodes]->offset;
    for (const Section* sec : {o.find[kNodes], o.find[kSizes], o.find[kColours]})
      if (sec) file_bytes = std::max(file_bytes, sec->offset + sec->bytes);
  }
  // The traversal numbers pages with 32 bits; absolute word pointers are 32-bit stream words (relative ones
  // count from their level's 64-bit start).
  const bool words_reach = !starts_.empty() || pi.head.words <= (uint64_t{1} << 32);
  if (!words_reach || pi.hashes.size() >= UINT32_MAX)
    throw Error(path + ": its paged stream holds " + std::to_string(pi.head.words) + " words in " +
                std::to_string(pi.hashes.size()) + " pages, past what this megavox streams (" +
                (words_reach ? "2^32 - 1 pages" : "2^32 words for absolute pointers") + ")");
  page_words_ = pi.head.page_words;
  order_ = static_cast<NodeOrder>(pi.head.order);
  words_ = pi.head.words;
  hashes_ = std::move(pi.hashes);
  map_ = io::MappedFile(path);
  if (map_.size() < file_bytes) throw Error(path + ": truncated: it changed since its header was read");
}

bool MvxPages::read_sizes(uint32_t page, std::span<uint32_t> out, std::string* error) const {
  if (plane_words_ == 0) {
    if (error) *error = path_ + ": no size plane (written before .mvx version 5)";
    return false;
  }
  return read_mapped(page, out, error, sizes_offset_, words_ * (plane_words_ / page_words_), plane_words_,
                     size_hashes_, "size plane page ");
}

uint32_t MvxPages::colour(uint64_t e) const {
  if (e >= colour_entries_) throw Error(path_ + ": colour entry " + std::to_string(e) + " of " + std::to_string(colour_entries_));
  auto copy = [&](void* to, uint64_t at, uint64_t bytes) {  // (the file may shrink while mapped)
    if (!io::copy_mapped(to, map_.data() + colours_offset_ + at, bytes))
      throw Error(path_ + ": the file is shorter than when it was opened (truncated while in use)");
  };
  // (the head was read and checked at open: one copy of the entry's bytes per call)
  if (colour_format_ == kColourRaw24) {
    uint8_t c[3];
    copy(c, sizeof(ColourHead) + 3 * e, 3);
    return c[0] | uint32_t{c[1]} << 8 | uint32_t{c[2]} << 16;
  }
  std::call_once(palette_once_, [&] {
    std::vector<uint8_t> body(colour_bytes_ - sizeof(ColourHead));
    copy(body.data(), sizeof(ColourHead), body.size());
    try {
      palette_ = std::make_shared<const ColourPalette>(
          palette_parse(body, colour_entries_, palette_counts_[0], palette_counts_[1]));
    } catch (const Error& err) {
      throw Error(path_ + ": " + err.what());
    }
  });
  const std::array<uint8_t, 3> c = palette_->colour(e);
  return c[0] | uint32_t{c[1]} << 8 | uint32_t{c[2]} << 16;
}

bool MvxPages::is_paged(const std::string& path) {
  const Opened o = open_file(path);
  check_voxel_file(o, path);
  return o.find[kPageIndex] != nullptr;
}

bool MvxPages::read_page(uint32_t page, std::span<uint32_t> out, std::string* error) const {
  return read_mapped(page, out, error, nodes_offset_, words_, page_words_, hashes_, "page ");
}

bool MvxPages::read_mapped(uint32_t page, std::span<uint32_t> out, std::string* error, uint64_t offset,
                           uint64_t total, uint32_t per_page, const std::vector<uint64_t>& hashes,
                           const char* what) const {
  auto fail = [&](const std::string& why) {
    if (error) *error = path_ + ": " + what + std::to_string(page) + ": " + why;
    return false;
  };
  if (page >= pages()) return fail("past the end (" + std::to_string(pages()) + " pages)");
  if (out.size() != per_page)
    return fail("a buffer of " + std::to_string(out.size()) + " words for pages of " + std::to_string(per_page));
  const uint64_t first = uint64_t{page} * per_page;
  const uint64_t count = std::min<uint64_t>(per_page, total - first);
  if (!io::copy_mapped(out.data(), map_.data() + offset + first * 4, count * 4))
    return fail(errno == EFAULT ? std::string("the file is shorter than when it was opened (truncated while in use)")
                                : std::string("read error: ") + std::strerror(errno));
  std::fill(out.begin() + count, out.end(), 0u);
  if (hash(out.data(), out.size_bytes()) != hashes[page]) return fail("checksum mismatch (the file is damaged)");
  return true;
}

}  // namespace mv
