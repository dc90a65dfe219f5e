#include "mvx_pages.h"


#include <algorithm>
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
    nodes_offset_ = o.find[kNodes]->offset;
    file_bytes = nodes_offset_ + o.find[kNodes]->bytes;
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

bool MvxPages::is_paged(const std::string& path) {
  const Opened o = open_file(path);
  check_voxel_file(o, path);
  return o.find[kPageIndex] != nullptr;
}

bool MvxPages::read_page(uint32_t page, std::span<uint32_t> out, std::string* error) const {
  auto fail = [&](const std::string& why) {
    if (error) *error = path_ + ": page " + std::to_string(page) + ": " + why;
    return false;
  };
  if (page >= pages()) return fail("past the end (" + std::to_string(pages()) + " pages)");
  if (out.size() != page_words_)
    return fail("a buffer of " + std::to_string(out.size()) + " words for pages of " + std::to_string(page_words_));
  const uint64_t first = uint64_t{page} * page_words_;
  const uint64_t count = std::min<uint64_t>(page_words_, words_ - first);
  if (!io::copy_mapped(out.data(), map_.data() + nodes_offset_ + first * 4, count * 4))
    return fail(errno == EFAULT ? std::string("the file is shorter than when it was opened (truncated while in use)")
                                : std::string("read error: ") + std::strerror(errno));
  std::fill(out.begin() + count, out.end(), 0u);
  if (hash(out.data(), out.size_bytes()) != hashes_[page]) return fail("checksum mismatch (the file is damaged)");
  return true;
}

}  // namespace mv
