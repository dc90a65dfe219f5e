// The COPC hierarchy reader (copc_hierarchy.h).
#include "copc_hierarchy.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <set>

#include "io/file_ops.h"
#include "io/header_numbers.h"
#include "megavox/error.h"

namespace mv::laz {

namespace {

using io::detail::num;

template <class T>
T copc_le(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);  // COPC is little-endian, as megavox's hosts are
  return v;
}

constexpr uint64_t kCopcEntryBytes = 32;
constexpr int32_t kCopcMaxDepth = 32;

}  // namespace

void CopcNode::cube(const CopcInfo& info, double lo[3], double hi[3]) const {
  const double side = 2 * info.halfsize / std::ldexp(1.0, depth);
  const int32_t key[3] = {x, y, z};
  for (int a = 0; a < 3; ++a) {
    lo[a] = info.center[a] - info.halfsize + side * key[a];
    hi[a] = lo[a] + side;
  }
}

std::optional<CopcInfo> parse_copc_info(const uint8_t* b, size_t size) {
  if (size != 160) return std::nullopt;
  CopcInfo info;
  for (int a = 0; a < 3; ++a) info.center[a] = copc_le<double>(b + 8 * a);
  info.halfsize = copc_le<double>(b + 24);
  info.spacing = copc_le<double>(b + 32);
  info.root_offset = copc_le<uint64_t>(b + 40);
  info.root_size = copc_le<uint64_t>(b + 48);
  for (double v : {info.center[0], info.center[1], info.center[2], info.halfsize})
    if (!std::isfinite(v)) return std::nullopt;
  if (!(info.halfsize > 0)) return std::nullopt;
  return info;
}

std::vector<CopcNode> read_copc_nodes(std::FILE* file, const std::string& path, uint64_t file_size,
                                      const CopcInfo& info) {
  auto fail = [&](const std::string& what) { throw Error(path + ": corrupt COPC hierarchy: " + what); };
  std::vector<CopcNode> nodes;
  std::vector<std::pair<uint64_t, uint64_t>> pages = {{info.root_offset, info.root_size}};
  std::set<uint64_t> seen;
  while (!pages.empty()) {
    const auto [offset, size] = pages.back();
    pages.pop_back();
    if (size % kCopcEntryBytes != 0) fail("a page of " + num(size) + " bytes is not whole 32-byte entries");
    if (offset > file_size || size > file_size - offset)
      fail("the page at byte " + num(offset) + " (" + num(size) + " bytes) runs past the end of the file");
    if (!seen.insert(offset).second) fail("the page at byte " + num(offset) + " is listed twice");
    const std::vector<uint8_t> page = io::read_at(file, offset, size, path);  // inside the file: checked above
    for (uint64_t at = 0; at < size; at += kCopcEntryBytes) {
      const uint8_t* e = page.data() + at;
      CopcNode n;
      n.depth = copc_le<int32_t>(e);
      n.x = copc_le<int32_t>(e + 4);
      n.y = copc_le<int32_t>(e + 8);
      n.z = copc_le<int32_t>(e + 12);
      const uint64_t where = copc_le<uint64_t>(e + 16);
      const int32_t bytes = copc_le<int32_t>(e + 24), points = copc_le<int32_t>(e + 28);
      if (n.depth < 0 || n.depth > kCopcMaxDepth) fail("a node of depth " + std::to_string(n.depth));
      const int64_t span = int64_t{1} << n.depth;
      for (int32_t k : {n.x, n.y, n.z})
        if (k < 0 || k >= span) fail("node key " + std::to_string(k) + " outside depth " + std::to_string(n.depth));
      if (points == -1) {  // a child page
        if (bytes < 0) fail("a child page of " + std::to_string(bytes) + " bytes");
        pages.push_back({where, static_cast<uint64_t>(bytes)});
        continue;
      }
      if (points < -1 || bytes < 0) fail("an entry of " + std::to_string(points) + " points in " + std::to_string(bytes) + " bytes");
      if (points == 0) continue;
      n.offset = where;
      n.bytes = static_cast<uint64_t>(bytes);
      n.points = static_cast<uint64_t>(points);
      nodes.push_back(n);
    }
  }
  return nodes;
}

}  // namespace mv::laz
