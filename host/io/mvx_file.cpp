// Reading and writing .mvx files (layout in include/megavox/mvx.h).
#include <xxhash.h>

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "atomic_file.h"
#include "megavox/error.h"
#include "megavox/mvx.h"

namespace mv {

static_assert(std::endian::native == std::endian::little, ".mvx I/O assumes a little-endian host");

namespace {

constexpr char kMagic[8] = {'M', 'E', 'G', 'A', 'V', 'O', 'X', '\x1a'};
constexpr uint64_t kPage = 4096;
constexpr uint32_t kMaxSections = 16;
enum SectionKind : uint32_t { kCounts = 1, kLevels = 2, kNodes = 3, kInner = 4, kBricks = 5 };
constexpr uint32_t kKinds = 6;

struct Section {
  uint32_t kind = 0, reserved = 0;
  uint64_t offset = 0, bytes = 0, checksum = 0;
};

struct Header {
  char magic[8];
  uint32_t version, encoding, levels, sections;
  double origin[3], voxel_size;
  uint32_t resolution, reserved;
  double bounds_lo[3], bounds_hi[3];
  uint64_t voxels;
  Section table[kMaxSections];
  uint64_t checksum;  // XXH3-64 of the bytes above
};
static_assert(sizeof(Header) < kPage);

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

uint64_t hash(const void* data, size_t bytes) { return XXH3_64bits(data, bytes); }

template <class T>
std::vector<T> section_data(std::FILE* f, const Section& s, const std::string& path, const char* what) {
  if (s.bytes % sizeof(T)) throw Error(path + ": " + what + " section has a partial element");
  std::vector<T> v(s.bytes / sizeof(T));
  if (std::fseek(f, static_cast<long>(s.offset), SEEK_SET) != 0 || std::fread(v.data(), 1, s.bytes, f) != s.bytes)
    throw Error(path + ": truncated: the " + what + " section ends past the end of the file");
  if (hash(v.data(), s.bytes) != s.checksum) throw Error(path + ": checksum mismatch in the " + what + " section");
  return v;
}

}  // namespace

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

void write_mvx(const std::string& path, const MvxFile& in) {
  const uint32_t L = in.dag.levels;
  std::vector<uint64_t> counts = in.svo_nodes;
  counts.insert(counts.end(), in.dag_nodes.begin(), in.dag_nodes.end());
  struct Blob {
    uint32_t kind;
    const void* data;
    uint64_t bytes;
  };
  std::vector<Blob> blobs = {{kCounts, counts.data(), counts.size() * 8},
                             {kLevels, in.dag.level_offset.data(), in.dag.level_offset.size() * 8}};
  if (in.dag.encoding == Encoding::ssvdag) {
    blobs.push_back({kInner, in.dag.inner.data(), in.dag.inner.size() * 2});
    blobs.push_back({kBricks, in.dag.bricks.data(), in.dag.bricks.size() * 8});
  } else {
    blobs.push_back({kNodes, in.dag.words.data(), in.dag.words.size() * 4});
  }
  Header h{};
  std::memcpy(h.magic, kMagic, 8);
  h.version = kMvxVersion;
  h.encoding = static_cast<uint32_t>(in.dag.encoding);
  h.levels = L;
  h.sections = static_cast<uint32_t>(blobs.size());
  for (int a = 0; a < 3; ++a) {
    h.origin[a] = in.grid.origin[a];
    h.bounds_lo[a] = in.bounds.lo[a];
    h.bounds_hi[a] = in.bounds.hi[a];
  }
  h.voxel_size = in.grid.voxel_size;
  h.resolution = in.grid.resolution;
  h.voxels = in.voxels;
  uint64_t offset = kPage;
  for (uint32_t i = 0; i < h.sections; ++i) {
    h.table[i] = {blobs[i].kind, 0, offset, blobs[i].bytes, hash(blobs[i].data, blobs[i].bytes)};
    offset += (blobs[i].bytes + kPage - 1) / kPage * kPage;
  }
  h.checksum = hash(&h, offsetof(Header, checksum));

  io::write_atomically(path, [&](std::FILE* f) {
    std::vector<char> page(kPage, 0);
    std::memcpy(page.data(), &h, sizeof h);
    bool ok = std::fwrite(page.data(), 1, kPage, f) == kPage;
    for (uint32_t i = 0; ok && i < h.sections; ++i) {
      ok = std::fwrite(blobs[i].data, 1, blobs[i].bytes, f) == blobs[i].bytes;
      uint64_t pad = (kPage - blobs[i].bytes % kPage) % kPage;
      std::vector<char> zeros(pad, 0);
      ok = ok && std::fwrite(zeros.data(), 1, pad, f) == pad;
    }
    return ok;
  });
}

MvxFile read_mvx(const std::string& path) {
  File f(std::fopen(path.c_str(), "rb"));
  if (!f) throw Error("cannot open '" + path + "': " + std::strerror(errno));
  std::fseek(f.get(), 0, SEEK_END);
  const auto file_bytes = static_cast<uint64_t>(std::ftell(f.get()));
  std::fseek(f.get(), 0, SEEK_SET);
  Header h{};
  if (std::fread(&h, 1, sizeof h, f.get()) != sizeof h || file_bytes < kPage) {
    if (file_bytes >= 8 && std::memcmp(h.magic, kMagic, 8) != 0) throw Error(path + ": not a .mvx file (bad magic)");
    throw Error(path + ": truncated: shorter than the 4 KiB .mvx header");
  }
  if (std::memcmp(h.magic, kMagic, 8) != 0) throw Error(path + ": not a .mvx file (bad magic)");
  if (h.version != kMvxVersion)
    throw Error(path + ": .mvx version " + std::to_string(h.version) + " (this megavox reads version " +
                std::to_string(kMvxVersion) + ")");
  if (hash(&h, offsetof(Header, checksum)) != h.checksum) throw Error(path + ": header checksum mismatch");
  if (h.encoding < static_cast<uint32_t>(Encoding::svo) || h.encoding > static_cast<uint32_t>(Encoding::ssvdag))
    throw Error(path + ": unknown encoding " + std::to_string(h.encoding));
  const bool compact = h.encoding == static_cast<uint32_t>(Encoding::ssvdag);
  if (h.levels < 1 || h.levels > 21) throw Error(path + ": bad level count " + std::to_string(h.levels));
  if (h.resolution != (1u << h.levels)) throw Error(path + ": resolution does not match the level count");
  if (!(h.voxel_size > 0) || h.sections != (compact ? 4u : 3u)) throw Error(path + ": bad grid or section count");
  const Section* find[kKinds] = {};
  uint64_t expected_bytes = kPage;
  for (uint32_t i = 0; i < h.sections; ++i) {
    const Section& s = h.table[i];
    const bool wanted = s.kind == kCounts || s.kind == kLevels || (compact ? s.kind == kInner || s.kind == kBricks
                                                                            : s.kind == kNodes);
    if (!wanted || find[s.kind]) throw Error(path + ": bad section table");
    if (s.offset % kPage || s.offset < kPage || s.offset > file_bytes || s.bytes > file_bytes - s.offset)
      throw Error(path + ": truncated: section " + std::to_string(i) + " ends past the end of the file");
    find[s.kind] = &s;
    expected_bytes = std::max(expected_bytes, s.offset + (s.bytes + kPage - 1) / kPage * kPage);
  }
  if (file_bytes < expected_bytes) throw Error(path + ": truncated: " + std::to_string(file_bytes) + " bytes of " +
                                               std::to_string(expected_bytes));
  if (file_bytes > expected_bytes) throw Error(path + ": " + std::to_string(file_bytes - expected_bytes) +
                                               " unexpected bytes after the last section");
  MvxFile out;
  out.grid.resolution = h.resolution;
  out.grid.voxel_size = h.voxel_size;
  for (int a = 0; a < 3; ++a) {
    out.grid.origin[a] = h.origin[a];
    out.bounds.lo[a] = h.bounds_lo[a];
    out.bounds.hi[a] = h.bounds_hi[a];
  }
  out.voxels = h.voxels;
  auto counts = section_data<uint64_t>(f.get(), *find[kCounts], path, "counts");
  if (counts.size() != 2 * (uint64_t{h.levels} + 1)) throw Error(path + ": counts section has the wrong size");
  out.svo_nodes.assign(counts.begin(), counts.begin() + h.levels + 1);
  out.dag_nodes.assign(counts.begin() + h.levels + 1, counts.end());
  out.dag.encoding = static_cast<Encoding>(h.encoding);
  out.dag.levels = h.levels;
  out.dag.level_offset = section_data<uint64_t>(f.get(), *find[kLevels], path, "levels");
  if (compact) {
    out.dag.inner = section_data<uint16_t>(f.get(), *find[kInner], path, "inner nodes");
    out.dag.bricks = section_data<uint64_t>(f.get(), *find[kBricks], path, "bricks");
  } else {
    out.dag.words = section_data<uint32_t>(f.get(), *find[kNodes], path, "nodes");
  }
  try {
    validate_encoded(out.dag);
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }
  return out;
}

}  // namespace mv
