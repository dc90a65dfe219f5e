// COPC (Cloud Optimized Point Cloud): a LAS 1.4 LAZ file whose chunks are the nodes of an octree, with the
// octree in a hierarchy of pages (COPC 1.0: the "copc" info record, user id "copc", record 1, and hierarchy
// pages of 32-byte entries). A reader that wants part of the cloud decodes only the chunks whose node cube
// meets the part.
#pragma once
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace mv::laz {

struct CopcInfo {
  double center[3] = {0, 0, 0};
  double halfsize = 0;  // the root cube is center +- halfsize on each axis, in world units
  double spacing = 0;
  uint64_t root_offset = 0, root_size = 0;  // the root hierarchy page
};

// One node that holds points: its octree key and the chunk that stores them.
struct CopcNode {
  int32_t depth = 0, x = 0, y = 0, z = 0;
  uint64_t offset = 0;  // the chunk's first byte in the file
  uint64_t bytes = 0;
  uint64_t points = 0;

  // The node's cube in world units: min and max corners.
  void cube(const CopcInfo& info, double lo[3], double hi[3]) const;
};

// The info record's payload (160 bytes); nullopt when `size` is wrong or its numbers are not finite.
std::optional<CopcInfo> parse_copc_info(const uint8_t* bytes, size_t size);

// Every node with points, walking the hierarchy pages from the root page (each page read once, inside the
// file, depths and keys checked). Throws mv::Error naming `path` and the fault.
std::vector<CopcNode> read_copc_nodes(std::FILE* file, const std::string& path, uint64_t file_size,
                                      const CopcInfo& info);

}  // namespace mv::laz
