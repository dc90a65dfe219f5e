// Voxels and their depth-first colours from a cloud's cells, on the device (megavox/colour.h,
// kernels/common/colour.h). The points' planes are summed over each voxel's run (one segmented_sum) and divided;
// then every node above comes from the voxels' codes at once: how many nodes start at each voxel, their
// pre-order places by one scan of those counts, their means by differences of the voxels' channel prefix sums.
// A fixed handful of dispatches and one wait, whatever the depth.
#include <algorithm>
#include <bit>
#include <chrono>
#include <cstring>
#include <string>

#include "common/colour.h"
#include "megavox/colour.h"
#include "megavox/error.h"
#include "megavox/primitives.h"
#include "megavox/segmented.h"

namespace mv {

namespace {

constexpr uint32_t kColourLocal = 64;
constexpr uint32_t kColourPlanes = MV_COLOUR_PLANES;

Buffer colour_alloc(Device& dev, uint64_t bytes, const char* what) { return dev.alloc(std::max<uint64_t>(bytes, 8), what); }

void colour_dispatch(Device& dev, KernelId id, uint64_t n, std::initializer_list<const Buffer*> buffers,
                     MvColourParams p) {
  if (n) dev.dispatch(dev.kernel(id), dev.groups_for(n, kColourLocal), kColourLocal, buffers, p);
  dev.barrier();
}

// The checks before the voxels' planes (d, r, g, b: 4 x voxels 32-bit values) are made.
void check_voxels(Device& dev, const Buffer& keys, uint64_t voxels, uint32_t levels) {
  uint64_t last_key = 0;
  dev.download(keys, &last_key, 8, (voxels - 1) * 8);
  if (levels < 21 && last_key >> (3 * levels) != 0)
    throw Error("voxel colours: a voxel's code is outside the octree of " + std::to_string(levels) + " levels");
  if (4 * voxels > kMaxDeviceItems)
    throw Error("voxel colours: " + std::to_string(voxels) + " voxels, over the " +
                std::to_string(kMaxDeviceItems / 4) + " one device call holds");
}

// The depth-first colours of the octree over `voxels` sorted voxel codes (keys), the root at level `levels`, from
// the voxels' planes (colour_starts or colour_level).
std::vector<uint8_t> node_colours(Device& dev, const Buffer& keys, const Buffer& planes, uint64_t voxels,
                                  uint32_t levels, ColourSums width) {
  MvColourParams p{};
  p.n = static_cast<uint32_t>(voxels);
  p.levels = levels;
  // 32-bit sums where no node's channel sum reaches 2^32 (colour.h): half the scan's output.
  const bool wide = width == ColourSums::wide || voxels * 255 >= (uint64_t{1} << 32);
  const uint64_t word = wide ? 8 : 4;
  Buffer sums = colour_alloc(dev, (4 * voxels + 1) * word, "voxel colour prefix sums");
  if (wide) exclusive_scan64(dev, planes, sums, 4 * voxels);
  else exclusive_scan(dev, planes, sums, 4 * voxels);
  dev.barrier();
  uint64_t entries = 0;  // the sum of the nodes starting at each voxel (below 2^32: checked against the maximum)
  dev.download(sums, &entries, word, voxels * word);
  if (entries > kMaxDeviceItems)
    throw Error("voxel colours: " + std::to_string(entries) + " octree nodes, over the " +
                std::to_string(kMaxDeviceItems) + " one attribute array holds");
  Buffer attributes = colour_alloc(dev, entries * 4, "depth-first colours");
  colour_dispatch(dev, wide ? KernelId::colour_nodes_wide : KernelId::colour_nodes, voxels,
                  {&keys, &planes, &sums, &attributes}, p);
  // Read in place where the device computes in host memory (no copy of the packed words), else downloaded.
  std::vector<uint32_t> downloaded;
  const auto* packed = static_cast<const uint32_t*>(dev.host_view(attributes));
  if (packed) {
    dev.finish();
  } else {
    downloaded.resize(entries);
    dev.download(attributes, downloaded.data(), entries * 4);
    packed = downloaded.data();
  }
  // Each word's low three bytes are its RGB24 (little-endian): a 4-byte store a word, the fourth byte overwritten
  // by the next word's (or left past the end, which the resize drops).
  static_assert(std::endian::native == std::endian::little);
  std::vector<uint8_t> out(entries * 3 + 1);
  for (uint64_t i = 0; i < entries; ++i) std::memcpy(&out[3 * i], &packed[i], 4);
  out.resize(entries * 3);
  return out;
}

// `sorted_rgb`: the points' colours in sorted order, one per `stride` 32-bit words; `runs`: the points' runs of
// equal codes (one a voxel), when points > voxels.
std::vector<uint8_t> depth_first_colours(Device& dev, const Buffer& sorted_rgb, uint32_t stride, const Segmentation* runs,
                                         uint64_t points, const Buffer& voxel_keys, uint64_t voxels, uint32_t levels,
                                         ColourSums width) {
  // The sort's scratch is retired, not yet free: reused once the device is idle (one wait), the buffers below land
  // in storage already touched instead of fresh memory (a CPU device faults on each fresh page).
  dev.finish();
  check_voxels(dev, voxel_keys, voxels, levels);
  if (points != voxels && (!runs || runs->count != voxels))
    throw Error("voxel colours: the points' runs disagree with the voxels");
  MvColourParams p{};
  p.levels = levels;
  p.stride = stride;
  Buffer planes = colour_alloc(dev, 4 * voxels * 4, "voxel colour planes");
  if (points == voxels) {  // one point a voxel (a mesh's voxels, or a sparse cloud): its colour is the voxel's
    p.n = static_cast<uint32_t>(voxels);
    colour_dispatch(dev, KernelId::colour_starts, voxels, {&voxel_keys, &sorted_rgb, &planes}, p);
  } else {
    Buffer point_planes = colour_alloc(dev, kColourPlanes * points * 4, "point colour planes");
    p.n = static_cast<uint32_t>(points);
    colour_dispatch(dev, KernelId::colour_unpack, points, {&sorted_rgb, &point_planes}, p);
    Buffer sums = colour_alloc(dev, kColourPlanes * voxels * 8, "colour sums");
    segmented_sum(dev, *runs, point_planes, sums, kColourPlanes);
    p.n = static_cast<uint32_t>(voxels);
    colour_dispatch(dev, KernelId::colour_level, voxels, {&voxel_keys, &sums, &planes}, p);
  }
  return node_colours(dev, voxel_keys, planes, voxels, levels, width);
}

}  // namespace

std::vector<uint8_t> depth_first_voxel_colours(Device& dev, Buffer voxel_keys, const Buffer& voxel_rgb, uint64_t voxels,
                                               uint32_t levels, ColourSums width) {
  if (voxels == 0) return {};
  // one colour a voxel: no runs of points to find, so no point codes
  return depth_first_colours(dev, voxel_rgb, 1, nullptr, voxels, voxel_keys, voxels, levels, width);
}

CloudVoxels voxelize_cloud(Device& dev, std::span<const uint32_t> cells, std::span<const uint32_t> rgb,
                           uint32_t levels, double* colour_seconds, ColourSums width) {
  if (levels < 1 || levels > 21) throw Error("voxelize_cloud: " + std::to_string(levels) + " levels (1 to 21)");
  const uint64_t points = cells.size() / 3;
  const bool colour = !rgb.empty();
  if (colour && rgb.size() != points)
    throw Error("voxelize_cloud: " + std::to_string(rgb.size()) + " colours for " + std::to_string(points) + " points");
  const uint64_t most = colour ? kMaxDeviceItems / kColourPlanes : kMaxDeviceItems;
  if (points > most)
    throw Error("voxelize_cloud: " + std::to_string(points) + " points, over the " + std::to_string(most) +
                " one device call holds" + (colour ? " with colour" : ""));
  CloudVoxels out;
  if (points == 0) return out;
  Buffer keys = dev.alloc(points * 8, "point codes");
  {
    Buffer xyz = dev.alloc(points * 12, "point cells");
    dev.upload(xyz, cells.data(), points * 12);
    dev.barrier();
    morton_encode(dev, xyz, keys, points, KeyBits::k64);
    dev.barrier();
  }
  Buffer values;
  if (colour) {
    values = dev.alloc(points * 4, "point colours");
    dev.upload(values, rgb.data(), points * 4);
    dev.barrier();
  }
  // Where the codes leave 24 bits, each point's colour rides below its code in the sort key: the sort then moves
  // no colour column (on lavapipe that column doubled the scatter's time).
  const bool packed = colour && 3 * levels + MV_COLOUR_PAYLOAD <= 64;
  if (packed) {
    MvColourParams p{};
    p.n = static_cast<uint32_t>(points);
    colour_dispatch(dev, KernelId::colour_pack_keys, points, {&keys, &values}, p);
    values = Buffer();
    radix_sort_packed(dev, keys, points, MV_COLOUR_PAYLOAD);
  } else {
    radix_sort(dev, keys, colour ? &values : nullptr, points, KeyBits::k64);
  }
  dev.barrier();
  if (!colour) {
    Buffer unique = dev.alloc(points * 8, "voxel codes");
    const uint64_t voxels = unique_sorted(dev, keys, unique, points);
    out.keys.resize(voxels);
    dev.download(unique, out.keys.data(), voxels * 8);
    return out;
  }
  // With colour the points' runs are needed anyway: the voxels are their first codes (one segmentation serves
  // both, instead of unique_sorted and a second pass over the same keys).
  const uint32_t payload = packed ? MV_COLOUR_PAYLOAD : 0;
  const Segmentation runs = segment_by_key(dev, keys, points, payload);
  const uint64_t voxels = runs.count;
  Buffer unique = dev.alloc(voxels * 8, "voxel codes");
  MvColourParams first{};
  first.n = static_cast<uint32_t>(voxels);
  first.shift = payload;
  colour_dispatch(dev, KernelId::colour_parent_keys, voxels, {&keys, &runs.starts, &unique}, first);
  out.keys.resize(voxels);
  dev.download(unique, out.keys.data(), voxels * 8);
  if (!packed) keys = Buffer();  // the points' codes are done with: their runs and the voxels' codes stay
  {
    const auto start = std::chrono::steady_clock::now();
    out.colours =
        depth_first_colours(dev, packed ? keys : values, packed ? 2 : 1, &runs, points, unique, voxels, levels, width);
    if (colour_seconds) *colour_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return out;
}

}  // namespace mv
