// Reading and writing .mvx files (layout in include/megavox/mvx.h).
#include <xxhash.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstddef>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <memory>
#include <new>

#include "atomic_file.h"
#include "paging/page_layout.h"
#include "paging/paged_sizes.h"
#include "paging/paged_ssvdag.h"
#include "paging/paged_stream.h"
#include "file_ops.h"
#include "mvx_format.h"
#include "megavox/colour_palette.h"
#include "megavox/error.h"
#include "megavox/mvx.h"

namespace mv {

static_assert(std::endian::native == std::endian::little, ".mvx I/O assumes a little-endian host");

using namespace mvx_format;

std::string encoding_name(Encoding e) {
  switch (e) {
    case Encoding::svo:
      return "svo";
    case Encoding::svdag:
      return "svdag";
    case Encoding::ussvdag:
      return "ussvdag";
    case Encoding::ssvdag:
      return "ssvdag";
  }
  return "unknown(" + std::to_string(static_cast<uint32_t>(e)) + ")";
}

namespace {

bool is_power_of_two(uint32_t v) { return v && !(v & (v - 1)); }

// The paged stream of `dag` (with its page index) that write_mvx stores.
struct PagedNodes {
  std::vector<uint32_t> words;
  std::vector<uint64_t> index;   // PageIndexHead's 3 words, then the page hashes
  std::vector<uint64_t> starts;  // ssvdag: PagedSsvdag::starts; a word stream in level order: its levels' starts
  std::vector<uint64_t> level_offset;  // of the level-order stream the way back gives
  std::vector<uint32_t> sizes;         // with colours: the size plane (paged_sizes.h)
  std::vector<uint64_t> size_index;    // its SizeIndexHead's 2 words, then the page hashes
};

// The size plane of `p` and its index, for a file with colours.
void add_size_plane(PagedNodes& p, const EncodedDag& dag, uint32_t page_words) {
  p.sizes = paged_size_plane(dag.encoding, dag.levels, p.words, p.starts);
  const uint32_t k = size_plane_words(dag.encoding), plane_words = k * page_words;
  const SizeIndexHead head{plane_words, 0, (p.words.size() + page_words - 1) / page_words};
  p.size_index.resize(2 + head.pages);
  std::memcpy(p.size_index.data(), &head, sizeof head);
  for (uint64_t page = 0; page < head.pages; ++page)
    p.size_index[2 + page] = page_hash(p.sizes.data() + page * plane_words,
                                       std::min<uint64_t>(plane_words, p.sizes.size() - page * plane_words), plane_words);
}

// An ssvdag is always in level order (its offsets count from level starts; see paged_ssvdag.h).
PagedNodes paged_nodes(const EncodedDag& dag, const MvxPaging& paging) {
  if (!is_power_of_two(paging.page_words) || paging.page_words < kMinPageWords || paging.page_words > kMaxPageWords)
    throw Error(".mvx pages of " + std::to_string(paging.page_words) + " words: a power of two from " +
                std::to_string(kMinPageWords) + " to " + std::to_string(kMaxPageWords) + " is needed");
  PagedNodes p;
  NodeOrder order = paging.order;
  if (dag.encoding == Encoding::ssvdag) {
    PagedSsvdag s = paged_ssvdag(dag, paging.page_words);
    p.words = std::move(s.words);
    p.starts = std::move(s.starts);
    p.level_offset = std::move(s.level_offset);
    order = NodeOrder::level;
  } else {
    PageLayout layout = page_layout(dag, order, paging.page_words);
    if (layout.words > UINT32_MAX) {  // subtree pointers are absolute 32-bit words; level order's count per level
      order = NodeOrder::level;
      layout = page_layout(dag, order, paging.page_words);
    }
    EncodedDag stream = paged_stream(dag, layout);
    p.words = std::move(stream.words);
    p.starts = std::move(stream.level_offset);
    p.level_offset = dag.level_offset;
  }
  const uint64_t words = p.words.size(), pw = paging.page_words;
  const PageIndexHead head{paging.page_words, static_cast<uint32_t>(order), (words + pw - 1) / pw, words};
  p.index.resize(3 + head.pages);
  std::memcpy(p.index.data(), &head, sizeof head);
  for (uint64_t page = 0; page < head.pages; ++page)
    p.index[3 + page] = page_hash(p.words.data() + page * pw, std::min(pw, words - page * pw), paging.page_words);
  return p;
}

// The colour section as `in.colour_storage` asks: raw RGB24, the palette, or the smaller of the two.
std::vector<uint8_t> colour_section(const MvxFile& in, MvxColourStats& stats) {
  const uint64_t entries = in.colours.size() / 3;
  stats.entries = entries;
  std::vector<uint8_t> body;
  if (in.colour_bits < 1 || in.colour_bits > 24) throw Error("colour bits " + std::to_string(in.colour_bits) + ": 1 to 24");
  ColourHead head{kColourRaw24, in.colour_bits, entries, {0, 0}};
  if (in.colour_storage != ColourStorage::raw) {
    const auto t = std::chrono::steady_clock::now();
    const ColourPalette p = palette_encode(in.colours);
    std::vector<uint8_t> packed = palette_serialise(p);
    stats.palette_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    stats.palette_bytes = sizeof head + packed.size();
    if (in.colour_storage == ColourStorage::palette || packed.size() < in.colours.size()) {
      head = {kColourPalette24, in.colour_bits, entries, {p.blocks(), p.palettes()}};
      stats.blocks = p.blocks();
      stats.palettes = p.palettes();
      stats.palette_entries = p.palette_entries();
      stats.materials = p.materials_count();
      body = std::move(packed);
    }
  }
  const std::vector<uint8_t>& payload = head.format == kColourRaw24 ? in.colours : body;
  stats.format = head.format;
  std::vector<uint8_t> out(sizeof head + payload.size());
  std::memcpy(out.data(), &head, sizeof head);
  std::copy(payload.begin(), payload.end(), out.begin() + sizeof head);
  stats.bytes = out.size();
  return out;
}

uint64_t octree_node_total(const std::vector<uint64_t>& svo_nodes) {
  uint64_t n = 0;
  for (uint64_t c : svo_nodes) n += c;
  return n;
}

}  // namespace

MvxColourStats write_mvx(const std::string& path, const MvxFile& in, const MvxPaging& paging) {
  const uint32_t L = in.dag.levels;
  std::vector<uint64_t> counts = in.svo_nodes;
  counts.insert(counts.end(), in.dag_nodes.begin(), in.dag_nodes.end());
  PagedNodes paged;
  if (paging.page_words != 0) {
    paged = paged_nodes(in.dag, paging);
    if (!in.colours.empty()) add_size_plane(paged, in.dag, paging.page_words);
  }
  const std::vector<uint64_t>& levels = paging.page_words != 0 ? paged.level_offset : in.dag.level_offset;
  std::vector<Blob> blobs = {{kCounts, counts.data(), counts.size() * 8}, {kLevels, levels.data(), levels.size() * 8}};
  if (paging.page_words != 0) {
    blobs.push_back({kNodes, paged.words.data(), paged.words.size() * 4, false});
    blobs.push_back({kPageIndex, paged.index.data(), paged.index.size() * 8});
    if (!paged.starts.empty()) blobs.push_back({kPagedStarts, paged.starts.data(), paged.starts.size() * 8});
    if (!paged.sizes.empty()) {
      blobs.push_back({kSizeIndex, paged.size_index.data(), paged.size_index.size() * 8});
      blobs.push_back({kSizes, paged.sizes.data(), paged.sizes.size() * 4, false});
    }
  } else if (in.dag.encoding == Encoding::ssvdag) {
    blobs.push_back({kInner, in.dag.inner.data(), in.dag.inner.size() * 2});
    blobs.push_back({kBricks, in.dag.bricks.data(), in.dag.bricks.size() * 8});
  } else {
    blobs.push_back({kNodes, in.dag.words.data(), in.dag.words.size() * 4});
  }
  std::vector<uint8_t> colours;
  MvxColourStats stats;
  if (!in.colours.empty()) {
    if (in.colours.size() % 3 || in.colours.size() / 3 != octree_node_total(in.svo_nodes))
      throw Error(path + ": " + std::to_string(in.colours.size()) + " colour bytes for " +
                  std::to_string(octree_node_total(in.svo_nodes)) + " octree nodes");
    colours = colour_section(in, stats);
    blobs.push_back({kColours, colours.data(), colours.size()});
  }
  Header h{};
  h.version = kMvxVersion;
  h.content = kVoxels;
  h.encoding = static_cast<uint32_t>(in.dag.encoding);
  h.levels = L;
  for (int a = 0; a < 3; ++a) {
    h.origin[a] = in.grid.origin[a];
    h.bounds_lo[a] = in.bounds.lo[a];
    h.bounds_hi[a] = in.bounds.hi[a];
  }
  h.voxel_size = in.grid.voxel_size;
  h.resolution = in.grid.resolution;
  h.voxels = in.voxels;
  write_file(path, h, blobs);
  return stats;
}

namespace mvx_format {

void write_file(const std::string& path, Header& h, const std::vector<Blob>& blobs) {
  std::vector<StreamedBlob> streamed;
  for (const Blob& b : blobs)
    streamed.push_back({b.kind, b.bytes, [&b](const PutBytes& put) { put(b.data, b.bytes); }, b.checked});
  write_file(path, h, streamed);
}

void write_file(const std::string& path, Header& h, const std::vector<StreamedBlob>& blobs) {
  std::memcpy(h.magic, kMagic, 8);
  h.sections = static_cast<uint32_t>(blobs.size());
  uint64_t offset = kPage;
  for (uint32_t i = 0; i < h.sections; ++i) {
    h.table[i] = {blobs[i].kind, 0, offset, blobs[i].bytes, 0};
    offset += (blobs[i].bytes + kPage - 1) / kPage * kPage;
  }
  io::write_atomically(path, [&](std::FILE* f) {
    std::vector<char> page(kPage, 0);
    bool ok = io::write_all(f, page.data(), kPage);  // the header, once the sections' checksums are known
    std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)> state(XXH3_createState(), &XXH3_freeState);
    if (!state) throw std::bad_alloc();
    for (uint32_t i = 0; ok && i < h.sections; ++i) {
      XXH3_64bits_reset(state.get());
      uint64_t written = 0;
      blobs[i].write([&](const void* data, size_t bytes) {
        if (!ok || bytes == 0) return;
        if (written + bytes > blobs[i].bytes) throw Error("internal error: a .mvx section runs past its size");
        XXH3_64bits_update(state.get(), data, bytes);
        ok = io::write_all(f, data, bytes);
        written += bytes;
      });
      if (ok && written != blobs[i].bytes)
        throw Error("internal error: .mvx section " + std::to_string(blobs[i].kind) + " holds " + std::to_string(written) +
                    " bytes of " + std::to_string(blobs[i].bytes));
      if (blobs[i].checked) h.table[i].checksum = XXH3_64bits_digest(state.get());
      const uint64_t pad = (kPage - blobs[i].bytes % kPage) % kPage;
      ok = ok && io::write_all(f, page.data(), pad);
    }
    h.checksum = hash(&h, offsetof(Header, checksum));
    std::memcpy(page.data(), &h, sizeof h);
    ok = ok && std::fseek(f, 0, SEEK_SET) == 0 && io::write_all(f, page.data(), kPage);
    return ok;
  });
}

Opened open_file(const std::string& path) {
  Opened o;
  o.file = io::open_read(path);
  std::FILE* f = o.file.get();
  std::fseek(f, 0, SEEK_END);
  const auto file_bytes = static_cast<uint64_t>(std::ftell(f));
  std::fseek(f, 0, SEEK_SET);
  Header& h = o.header;
  if (io::read_some(f, &h, sizeof h, path) != sizeof h || file_bytes < kPage) {
    if (file_bytes >= 8 && std::memcmp(h.magic, kMagic, 8) != 0) throw Error(path + ": not a .mvx file (bad magic)");
    throw Error(path + ": truncated: shorter than the 4 KiB .mvx header");
  }
  if (std::memcmp(h.magic, kMagic, 8) != 0) throw Error(path + ": not a .mvx file (bad magic)");
  if (h.version < 1 || h.version > kMvxVersion)
    throw Error(path + ": .mvx version " + std::to_string(h.version) + " (this megavox reads versions 1 to " +
                std::to_string(kMvxVersion) + ")");
  if (hash(&h, offsetof(Header, checksum)) != h.checksum) throw Error(path + ": header checksum mismatch");
  if (h.version == 1 && h.content != kVoxels) throw Error(path + ": a version 1 .mvx holds voxels only");
  if (h.content > kPoints) throw Error(path + ": unknown content kind " + std::to_string(h.content));
  if (h.sections > kMaxSections) throw Error(path + ": bad section count");
  uint64_t expected_bytes = kPage;
  for (uint32_t i = 0; i < h.sections; ++i) {
    const Section& s = h.table[i];
    if (s.kind == 0 || s.kind >= kKinds || o.find[s.kind]) throw Error(path + ": bad section table");
    if (s.offset % kPage || s.offset < kPage || s.offset > file_bytes || s.bytes > file_bytes - s.offset)
      throw Error(path + ": truncated: section " + std::to_string(i) + " ends past the end of the file");
    o.find[s.kind] = &s;
    expected_bytes = std::max(expected_bytes, s.offset + (s.bytes + kPage - 1) / kPage * kPage);
  }
  if (file_bytes < expected_bytes) throw Error(path + ": truncated: " + std::to_string(file_bytes) + " bytes of " +
                                               std::to_string(expected_bytes));
  if (file_bytes > expected_bytes) throw Error(path + ": " + std::to_string(file_bytes - expected_bytes) +
                                               " unexpected bytes after the last section");
  if (o.find[kPageIndex] && (h.version < 3 || h.content != kVoxels))
    throw Error(path + ": bad section table (a page index in a version " + std::to_string(h.version) + " " +
                (h.content == kVoxels ? "voxel" : "point") + " file)");
  return o;
}

void check_voxel_file(const Opened& o, const std::string& path) {
  const Header& h = o.header;
  if (h.content == kPoints)
    throw Error(path + ": holds a point cloud (.mvx content 'points'), not voxels: use `megavox points info` or "
                "`megavox points render`");
  if (h.encoding < static_cast<uint32_t>(Encoding::svo) || h.encoding > static_cast<uint32_t>(Encoding::ssvdag))
    throw Error(path + ": unknown encoding " + std::to_string(h.encoding));
  const bool compact = h.encoding == static_cast<uint32_t>(Encoding::ssvdag);
  if (h.levels < 1 || h.levels > 21) throw Error(path + ": bad level count " + std::to_string(h.levels));
  if (h.resolution != (1u << h.levels)) throw Error(path + ": resolution does not match the level count");
  const bool paged = o.find[kPageIndex] != nullptr;
  // counts, levels, then inner + bricks (an unpaged ssvdag), nodes (unpaged), or nodes + page index (paged)
  // + paged level starts (a paged ssvdag)
  // paged level starts: a paged ssvdag's always, a paged word stream's in level order (version 5 on)
  const bool starts = o.find[kPagedStarts] != nullptr;
  // the size plane: a paged file's with colours (version 5 on), its index and its words
  const bool sizes = o.find[kSizeIndex] != nullptr;
  const uint32_t sections =
      (paged ? 4 : (compact ? 4 : 3)) + (starts ? 1 : 0) + (o.find[kColours] ? 1 : 0) + (sizes ? 2 : 0);
  if (o.find[kColours] && h.version < 4)
    throw Error(path + ": bad section table (voxel colours in a version " + std::to_string(h.version) + " file)");
  if (!(h.voxel_size > 0) || h.sections != sections) throw Error(path + ": bad grid or section count");
  const bool kinds_ok = o.find[kCounts] && o.find[kLevels] &&
                        (compact && !paged ? o.find[kInner] && o.find[kBricks] : o.find[kNodes] != nullptr) &&
                        (compact && paged ? starts : !starts || (paged && h.version >= 5)) &&
                        sizes == (o.find[kSizes] != nullptr) &&
                        sizes == (paged && o.find[kColours] && h.version >= 5);
  if (!kinds_ok) throw Error(path + ": bad section table");
}

std::vector<uint64_t> paged_level_starts(const Opened& o, const PageIndex& pi, const std::string& path) {
  const bool compact = o.header.encoding == static_cast<uint32_t>(Encoding::ssvdag);
  const bool level = pi.head.order == static_cast<uint32_t>(NodeOrder::level);
  if (compact && !level) throw Error(path + ": bad page index: a paged ssvdag is in level order");
  // word streams: relative pointers in level order from version 5 on, absolute ones before and in subtree order
  const bool relative = compact || (level && o.header.version >= 5);
  if (relative != (o.find[kPagedStarts] != nullptr))
    throw Error(path + ": bad section table (paged level starts " + (relative ? "missing" : "in a stream without them") + ")");
  return relative ? read_paged_starts(o, path) : std::vector<uint64_t>();
}

std::vector<uint64_t> read_paged_starts(const Opened& o, const std::string& path) {
  std::vector<uint64_t> starts = section_data<uint64_t>(o.file.get(), *o.find[kPagedStarts], path, "paged level starts");
  if (starts.size() != o.header.levels + 1u)
    throw Error(path + ": " + std::to_string(starts.size()) + " paged level starts for " +
                std::to_string(o.header.levels) + " levels");
  return starts;
}

uint64_t page_hash(const uint32_t* words, uint64_t count, uint32_t page_words) {
  if (count == page_words) return hash(words, count * 4);
  // A short last page hashes as if padded with zeros, streamed: no page-sized copy (up to 64 MiB) is made.
  static constexpr uint32_t kZeros[1024] = {};
  struct StateFree {
    void operator()(XXH3_state_t* s) const { XXH3_freeState(s); }
  };
  const std::unique_ptr<XXH3_state_t, StateFree> state(XXH3_createState());
  if (!state) throw std::bad_alloc();
  XXH3_64bits_reset(state.get());
  XXH3_64bits_update(state.get(), words, count * 4);
  for (uint64_t left = page_words - count; left > 0;) {
    const uint64_t n = std::min<uint64_t>(left, std::size(kZeros));
    XXH3_64bits_update(state.get(), kZeros, n * 4);
    left -= n;
  }
  return XXH3_64bits_digest(state.get());
}

PageIndex read_page_index(const Opened& o, const std::string& path) {
  const Section& s = *o.find[kPageIndex];
  auto fail = [&](const std::string& why) { return Error(path + ": bad page index: " + why); };
  if (s.bytes < sizeof(PageIndexHead)) throw fail("truncated (" + std::to_string(s.bytes) + " bytes)");
  const std::vector<uint64_t> raw = section_data<uint64_t>(o.file.get(), s, path, "page index");
  PageIndex pi;
  std::memcpy(&pi.head, raw.data(), sizeof pi.head);
  const PageIndexHead& h = pi.head;
  if (!is_power_of_two(h.page_words) || h.page_words < kMinPageWords || h.page_words > kMaxPageWords)
    throw fail("pages of " + std::to_string(h.page_words) + " words (a power of two from " +
               std::to_string(kMinPageWords) + " to " + std::to_string(kMaxPageWords) + " is needed)");
  if (h.order > static_cast<uint32_t>(NodeOrder::subtree)) throw fail("unknown node order " + std::to_string(h.order));
  const uint64_t node_bytes = o.find[kNodes]->bytes;
  if (h.words != node_bytes / 4 || node_bytes % 4)
    throw fail(std::to_string(h.words) + " words, but the nodes section holds " + std::to_string(node_bytes) + " bytes");
  const uint64_t needed = (h.words + h.page_words - 1) / h.page_words;  // (no product that could overflow)
  if (h.pages < needed)
    throw fail(std::to_string(h.pages) + " pages of " + std::to_string(h.page_words) + " words cannot hold " +
               std::to_string(h.words) + " words");
  if (h.pages > needed)
    throw fail(std::to_string(h.pages) + " pages for " + std::to_string(h.words) + " words (an empty page at the end)");
  if (raw.size() != 3 + h.pages)
    throw fail("holds " + std::to_string(raw.size() - 3) + " page hashes for " + std::to_string(h.pages) + " pages");
  pi.hashes.assign(raw.begin() + 3, raw.end());
  return pi;
}

SizeIndex read_size_index(const Opened& o, const PageIndex& pi, const std::string& path) {
  SizeIndex si;
  if (!o.find[kSizeIndex]) return si;
  auto fail = [&](const std::string& why) { return Error(path + ": bad size index: " + why); };
  const std::vector<uint64_t> raw = section_data<uint64_t>(o.file.get(), *o.find[kSizeIndex], path, "size index");
  if (raw.size() < 2) throw fail("truncated");
  std::memcpy(&si.head, raw.data(), sizeof si.head);
  const uint32_t k = size_plane_words(static_cast<Encoding>(o.header.encoding));
  if (si.head.plane_words != uint64_t{k} * pi.head.page_words || si.head.reserved != 0)
    throw fail(std::to_string(si.head.plane_words) + " plane words a page for pages of " +
               std::to_string(pi.head.page_words) + " words");
  if (si.head.pages != pi.head.pages || raw.size() != 2 + si.head.pages)
    throw fail(std::to_string(raw.size() - 2) + " hashes for " + std::to_string(pi.head.pages) + " pages");
  if (o.find[kSizes]->bytes != pi.head.words * k * 4)
    throw fail("the plane holds " + std::to_string(o.find[kSizes]->bytes) + " bytes for " +
               std::to_string(pi.head.words) + " stream words");
  si.hashes.assign(raw.begin() + 2, raw.end());
  return si;
}

}  // namespace mvx_format

MvxContent mvx_content(const std::string& path) {
  return open_file(path).header.content == kPoints ? MvxContent::points : MvxContent::voxels;
}

namespace {

// The paged nodes of `o` into out.dag, in level order: every page checked against the page index, the
// structure by level_order_stream, the level offsets against the levels section (already in out.dag).
void read_paged_nodes(const Opened& o, const std::string& path, MvxFile& out) {
  const PageIndex pi = read_page_index(o, path);
  const uint32_t pw = pi.head.page_words;
  EncodedDag paged;
  paged.encoding = out.dag.encoding;
  paged.levels = out.dag.levels;
  paged.words = section_data<uint32_t>(o.file.get(), *o.find[kNodes], path, "nodes", false);
  for (uint64_t p = 0; p < pi.head.pages; ++p)
    if (page_hash(paged.words.data() + p * pw, std::min<uint64_t>(pw, paged.words.size() - p * pw), pw) != pi.hashes[p])
      throw Error(path + ": checksum mismatch in page " + std::to_string(p) + " of the nodes");
  const bool compact = out.dag.encoding == Encoding::ssvdag;
  std::vector<uint64_t> starts = paged_level_starts(o, pi, path);
  EncodedDag level_order;
  try {
    if (compact) {
      level_order = ssvdag_from_pages(paged.words, starts, out.dag.levels, pw);
    } else {
      paged.level_offset = std::move(starts);
      level_order = level_order_stream(paged, pw);
    }
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }
  if (level_order.level_offset != out.dag.level_offset)
    throw Error(path + ": the paged nodes' levels disagree with the levels section");
  // the size plane (a file with colours): page by page, then against what the stream it sizes says
  const SizeIndex si = read_size_index(o, pi, path);
  if (o.find[kSizes]) {
    const uint32_t qw = si.head.plane_words;
    const std::vector<uint32_t> plane = section_data<uint32_t>(o.file.get(), *o.find[kSizes], path, "size plane", false);
    for (uint64_t p = 0; p < si.head.pages; ++p)
      if (page_hash(plane.data() + p * qw, std::min<uint64_t>(qw, plane.size() - p * qw), qw) != si.hashes[p])
        throw Error(path + ": checksum mismatch in page " + std::to_string(p) + " of the size plane");
    try {
      if (paged_size_plane(paged.encoding, paged.levels, paged.words, compact ? starts : paged.level_offset) != plane)
        throw Error("the size plane disagrees with the nodes");
    } catch (const Error& e) {
      throw Error(path + ": " + e.what());
    }
  }
  out.dag.words = std::move(level_order.words);
  out.dag.inner = std::move(level_order.inner);
  out.dag.bricks = std::move(level_order.bricks);
  out.paging = {pw, static_cast<NodeOrder>(pi.head.order)};
  out.paged_words = pi.head.words;
  out.size_plane = o.find[kSizes] != nullptr;
}

// The colour section, checked: its head, and one RGB24 entry per octree node the counts name, raw or in a
// palette checked whole (palette_parse).
void read_colours(const Opened& o, const std::string& path, MvxFile& out) {
  const std::vector<uint8_t> raw = section_data<uint8_t>(o.file.get(), *o.find[kColours], path, "colours");
  ColourHead head{};
  if (raw.size() < sizeof head) throw Error(path + ": the colours section is shorter than its head");
  std::memcpy(&head, raw.data(), sizeof head);
  const bool palette = head.format == kColourPalette24;
  if ((head.format != kColourRaw24 && !palette) || head.bits < 1 || head.bits > 24 ||
      (!palette && (head.counts[0] || head.counts[1])))
    throw Error(path + ": colours of unknown format " + std::to_string(head.format) + " (" +
                std::to_string(head.bits) + " bits)");
  const uint64_t nodes = octree_node_total(out.svo_nodes);
  if (head.entries != nodes)
    throw Error(path + ": " + std::to_string(head.entries) + " colours for " + std::to_string(nodes) + " octree nodes");
  MvxColourStats& stats = out.colour_stats;
  stats.format = head.format;
  stats.entries = head.entries;
  stats.bytes = raw.size();
  out.colour_bits = head.bits;
  if (palette) {
    ColourPalette p;
    try {
      p = palette_parse(std::span<const uint8_t>(raw).subspan(sizeof head), head.entries, head.counts[0], head.counts[1]);
    } catch (const Error& e) {
      throw Error(path + ": " + e.what());
    }
    if (p.materials_count() > uint64_t{1} << head.bits)
      throw Error(path + ": " + std::to_string(p.materials_count()) + " distinct colours in a " +
                  std::to_string(head.bits) + "-bit colour palette");
    stats.blocks = p.blocks();
    stats.palettes = p.palettes();
    stats.palette_entries = p.palette_entries();
    stats.materials = p.materials_count();
    out.colours = p.decode();
    out.colour_palette = std::make_shared<const ColourPalette>(std::move(p));
    return;
  }
  if (raw.size() - sizeof head != head.entries * 3)
    throw Error(path + ": the colours section holds " + std::to_string(raw.size() - sizeof head) + " bytes for " +
                std::to_string(head.entries) + " RGB24 colours");
  out.colours.assign(raw.begin() + sizeof head, raw.end());
}

}  // namespace

MvxFile read_mvx(const std::string& path) {
  Opened o = open_file(path);
  check_voxel_file(o, path);
  const Header& h = o.header;
  const bool compact = h.encoding == static_cast<uint32_t>(Encoding::ssvdag);
  const bool paged = o.find[kPageIndex] != nullptr;
  const Section* const* find = o.find;
  std::FILE* file = o.file.get();
  MvxFile out;
  out.grid.resolution = h.resolution;
  out.grid.voxel_size = h.voxel_size;
  for (int a = 0; a < 3; ++a) {
    out.grid.origin[a] = h.origin[a];
    out.bounds.lo[a] = h.bounds_lo[a];
    out.bounds.hi[a] = h.bounds_hi[a];
  }
  out.voxels = h.voxels;
  auto counts = section_data<uint64_t>(file, *find[kCounts], path, "counts");
  if (counts.size() != 2 * (uint64_t{h.levels} + 1)) throw Error(path + ": counts section has the wrong size");
  out.svo_nodes.assign(counts.begin(), counts.begin() + h.levels + 1);
  out.dag_nodes.assign(counts.begin() + h.levels + 1, counts.end());
  out.dag.encoding = static_cast<Encoding>(h.encoding);
  out.dag.levels = h.levels;
  out.dag.level_offset = section_data<uint64_t>(file, *find[kLevels], path, "levels");
  if (paged) {
    read_paged_nodes(o, path, out);
  } else if (compact) {
    out.dag.inner = section_data<uint16_t>(file, *find[kInner], path, "inner nodes");
    out.dag.bricks = section_data<uint64_t>(file, *find[kBricks], path, "bricks");
  } else {
    out.dag.words = section_data<uint32_t>(file, *find[kNodes], path, "nodes");
  }
  try {
    validate_encoded(out.dag);
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }
  if (find[kColours]) {
    // The colours' count comes from the counts section: tie it to the geometry before a palette section of a
    // few bytes may ask for that many colours.
    if (encoded_octree_nodes(out.dag) != out.svo_nodes)
      throw Error(path + ": the octree node counts do not match the DAG the file holds");
    read_colours(o, path, out);
  }
  return out;
}

}  // namespace mv
