#include "symvox_file.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

#include "atomic_file.h"
#include "file_ops.h"
#include "megavox/error.h"

namespace mv::io {

static_assert(std::endian::native == std::endian::little, "SymVox files are little-endian dumps");

namespace {

constexpr size_t kCommon = 36;        // bbox, root side, levels, nodes
constexpr size_t kHeader32 = 44;      // + first_leaf, words

template <class T>
bool put(std::FILE* f, const T* data, size_t count) {
  return write_all(f, data, sizeof(T) * count);
}

// A bounds-checked cursor over the file's bytes.
struct Reader {
  const std::vector<char>& bytes;
  const std::string& path;
  size_t at = 0;
  template <class T>
  T get(const char* what) {
    T v;
    take(&v, sizeof v, what);
    return v;
  }
  void take(void* out, size_t n, const char* what) {
    if (n > bytes.size() - at) throw Error(path + ": truncated in the " + what);
    if (n) std::memcpy(out, bytes.data() + at, n);  // an empty vector's data() may be null: memcpy's UB
    at += n;
  }
};

// The 32-bit layout does not store level boundaries: level L is the root alone; each next level starts at
// the smallest pointer of the level above (levels are stored in order, every node referenced). Returns
// whether any inner header carries mirror bits (a .ussvdag; an SVDAG is the mirror-free case).
bool recover_word_levels(SymvoxFile& f, uint32_t first_leaf, const std::string& path) {
  bool mirrors = false;
  const auto& w = f.dag.words;
  const uint32_t L = f.levels;
  f.dag.level_offset.assign(L + 1, 0);
  uint64_t begin = 0;
  for (uint32_t l = L; l >= 2; --l) {
    f.dag.level_offset[l] = begin;
    uint64_t next = w.size(), at = begin;
    while (at < next) {
      if (at >= w.size()) throw Error(path + ": level " + std::to_string(l) + " runs past the end of the words");
      const uint32_t mask = w[at] & 0xffu;
      mirrors = mirrors || (w[at] >> 8) != 0;
      if (mask == 0) throw Error(path + ": node at word " + std::to_string(at) + " has no children");
      const uint64_t size = 1 + std::popcount(mask);
      if (at + size > w.size()) throw Error(path + ": node at word " + std::to_string(at) + " is cut off");
      for (uint64_t k = 1; k < size; ++k) {
        if (w[at + k] <= at) throw Error(path + ": pointer at word " + std::to_string(at + k) + " points backwards");
        next = std::min<uint64_t>(next, w[at + k]);
      }
      at += size;
    }
    if (at != next) throw Error(path + ": level " + std::to_string(l) + " overlaps the level below it");
    begin = next;
  }
  f.dag.level_offset[1] = begin;
  if (L >= 2 && begin != first_leaf)
    throw Error(path + ": the 2x2x2 masks start at word " + std::to_string(begin) + ", the header says " +
                std::to_string(first_leaf));
  return mirrors;
}

}  // namespace

void write_symvox(const std::string& path, const SymvoxFile& file) {
  const EncodedDag& d = file.dag;
  const bool compact = d.encoding == Encoding::ssvdag;
  if (!compact && d.encoding != Encoding::svdag && d.encoding != Encoding::ussvdag)
    throw Error("SymVox files hold svdag, ussvdag or ssvdag DAGs");
  write_atomically(path, [&](std::FILE* f) {
    bool ok = put(f, file.bbox_min, 3) && put(f, file.bbox_max, 3) && put(f, &file.root_side, 1) &&
              put(f, &file.levels, 1) && put(f, &file.nodes, 1);
    if (!compact) {
      const uint32_t first_leaf = static_cast<uint32_t>(d.level_offset.at(1));
      const uint32_t words = static_cast<uint32_t>(d.words.size());
      return ok && put(f, &first_leaf, 1) && put(f, &words, 1) && put(f, d.words.data(), d.words.size());
    }
    const uint32_t n = static_cast<uint32_t>(d.inner.size()), m = static_cast<uint32_t>(d.bricks.size() * 8);
    std::vector<uint32_t> offsets;  // inner levels, root level first
    for (uint32_t l = d.levels; l >= 3; --l) offsets.push_back(static_cast<uint32_t>(d.level_offset.at(l)));
    const uint32_t k = static_cast<uint32_t>(offsets.size());
    return ok && put(f, &n, 1) && put(f, d.inner.data(), d.inner.size()) && put(f, &m, 1) &&
           put(f, d.bricks.data(), d.bricks.size()) && put(f, &k, 1) && put(f, offsets.data(), offsets.size());
  });
}

SymvoxFile read_symvox(const std::string& path) {
  const std::vector<char> bytes = read_whole_file(path);
  SymvoxFile f;
  f.file_bytes = bytes.size();
  Reader r{bytes, path};
  if (bytes.size() < kCommon) throw Error(path + ": too short for a SymVox-family header (" + std::to_string(bytes.size()) + " bytes)");
  r.take(f.bbox_min, 12, "header");
  r.take(f.bbox_max, 12, "header");
  f.root_side = r.get<float>("header");
  f.levels = r.get<uint32_t>("header");
  f.nodes = r.get<uint32_t>("header");
  if (f.levels < 1 || f.levels > 21)
    throw Error(path + ": not a SymVox-family file (its header says " + std::to_string(f.levels) +
                " levels; 1 to 21 expected)");
  if (!(f.root_side > 0) || !std::isfinite(f.root_side)) throw Error(path + ": the root side is not a positive number");
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(f.bbox_min[a]) || !std::isfinite(f.bbox_max[a]) || f.bbox_min[a] > f.bbox_max[a])
      throw Error(path + ": the bounding box is not a box");

  // Which layout: each declares its sizes; exactly one may account for every byte.
  bool word_layout = false;
  uint32_t first_leaf = 0, words = 0;
  if (bytes.size() >= kHeader32) {
    std::memcpy(&first_leaf, bytes.data() + 36, 4);
    std::memcpy(&words, bytes.data() + 40, 4);
    word_layout = kHeader32 + uint64_t{words} * 4 == bytes.size();
  }
  if (word_layout) {
    r.at = kHeader32;
    f.dag.words.resize(words);
    r.take(f.dag.words.data(), uint64_t{words} * 4, "node words");
    f.dag.levels = f.levels;
    if (words == 0) throw Error(path + ": holds no nodes");
    f.dag.encoding = recover_word_levels(f, first_leaf, path) ? Encoding::ussvdag : Encoding::svdag;
  } else {
    r.at = kCommon;
    const uint32_t n = r.get<uint32_t>("inner word count");
    if (uint64_t{n} * 2 > bytes.size() - r.at)
      throw Error(path + ": not a SymVox-family file (neither the 32-bit word count nor the 16-bit inner count fits its " +
                  std::to_string(bytes.size()) + " bytes)");
    f.dag.inner.resize(n);
    r.take(f.dag.inner.data(), uint64_t{n} * 2, "inner nodes");
    const uint32_t m = r.get<uint32_t>("brick byte count");
    if (m % 8) throw Error(path + ": the brick bytes (" + std::to_string(m) + ") are not whole 8-byte bricks");
    // Checked before the bricks are allocated: a garbage count would otherwise ask for up to 4 GiB.
    if (m > bytes.size() - r.at)
      throw Error(path + ": truncated: the brick byte count (" + std::to_string(m) + ") is more than the " +
                  std::to_string(bytes.size() - r.at) + " bytes left in the file");
    f.dag.bricks.resize(m / 8);
    r.take(f.dag.bricks.data(), m, "bricks");
    const uint32_t k = r.get<uint32_t>("level offset count");
    if (f.levels < 3 || k != f.levels - 2)
      throw Error(path + ": " + std::to_string(k) + " level offsets for " + std::to_string(f.levels) + " levels");
    std::vector<uint32_t> offsets(k);
    r.take(offsets.data(), uint64_t{k} * 4, "level offsets");
    if (r.at != bytes.size())
      throw Error(path + ": " + std::to_string(bytes.size() - r.at) + " unexpected bytes after the level offsets");
    f.dag.encoding = Encoding::ssvdag;
    f.dag.levels = f.levels;
    f.dag.level_offset.assign(f.levels + 1, 0);
    for (uint32_t i = 0; i < k; ++i) f.dag.level_offset[f.levels - i] = offsets[i];
  }
  try {
    validate_encoded(f.dag);
  } catch (const Error& e) {
    throw Error(path + ": " + e.what());
  }
  return f;
}

}  // namespace mv::io
