// Voxels and their depth-first colours from a cloud's cells, on the device (megavox/colour.h,
// kernels/common/colour.h). Bottom-up, the points' planes are summed over each voxel's run (one segmented_sum
// for the planes that can be nonzero) and divided, then each level's over its at most 8 children and divided in
// one pass (colour_parents); top-down, each node's pre-order index is its parent's + 1 + the subtree sizes of its
// earlier siblings (at most 7), and its colour is scattered there.
#include <algorithm>
#include <chrono>
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

// One level of the octree on the device: its nodes' codes, colours, planes and the runs of their parents.
struct ColourLevel {
  uint64_t n = 0;
  Buffer keys;    // n 64-bit codes at this level
  Buffer rgb;     // n packed 0xBBGGRR
  Buffer planes;  // kColourPlanes x n
  Buffer sizes;   // n subtree sizes (the size plane), kept for the top-down pass
  Segmentation by_parent;
};

Buffer colour_alloc(Device& dev, uint64_t bytes, const char* what) { return dev.alloc(std::max<uint64_t>(bytes, 8), what); }

void colour_dispatch(Device& dev, KernelId id, uint64_t n, std::initializer_list<const Buffer*> buffers,
                     MvColourParams p) {
  if (n) dev.dispatch(dev.kernel(id), dev.groups_for(n, kColourLocal), kColourLocal, buffers, p);
  dev.barrier();
}

// The 64-bit sums of the first `used` planes of `planes` over `runs`: used x m sums. One segmentation serves every
// plane.
Buffer colour_plane_sums(Device& dev, const Segmentation& runs, uint32_t used, const Buffer& planes) {
  const uint64_t m = runs.count;
  Buffer sums = colour_alloc(dev, used * m * 8, "colour sums");
  segmented_sum(dev, runs, planes, sums, used);
  return sums;
}

// Planes the level above must sum from `level`'s: the sums' high words only once a node of `level` can have
// 2^32 / 255 voxels or more below it (never for voxels, whose planes hold their 8-bit means).
uint32_t colour_planes_used(uint32_t level, uint64_t voxels) {
  if (level == 0) return MV_COLOUR_HIGH;
  const uint64_t most = level >= 21 ? voxels : std::min<uint64_t>(voxels, uint64_t{1} << (3 * level));
  return most * 255 < (uint64_t{1} << 32) ? MV_COLOUR_HIGH : kColourPlanes;
}

// `runs`: the points' runs of equal codes (one a voxel), when points > voxels.
std::vector<uint8_t> depth_first_colours(Device& dev, const Buffer& sorted_rgb, const Segmentation* runs,
                                         uint64_t points, Buffer voxel_keys, uint64_t voxels, uint32_t levels) {
  // The sort's scratch is retired, not yet free: reused once the device is idle (one wait), the sums below land
  // in storage already touched instead of fresh memory (a CPU device faults on each fresh page).
  dev.finish();
  std::vector<ColourLevel> lv(levels + 1);
  if (points == voxels) {  // one point a voxel (a mesh's voxels, or a sparse cloud): its colour is the voxel's
    ColourLevel& leaf = lv[0];
    leaf.n = voxels;
    leaf.keys = std::move(voxel_keys);
    leaf.rgb = colour_alloc(dev, voxels * 4, "node colours");
    dev.copy(sorted_rgb, leaf.rgb, voxels * 4, 0, 0);
    dev.barrier();
  } else {  // voxels from their points
    if (!runs || runs->count != voxels) throw Error("voxel colours: the points' runs disagree with the voxels");
    // a point's sample: its channels and a count of one, the only planes its voxel sums
    const uint32_t used = MV_COLOUR_COUNT + 1;
    Buffer planes = colour_alloc(dev, used * points * 4, "point colour planes");
    MvColourParams p{};
    p.n = static_cast<uint32_t>(points);
    colour_dispatch(dev, KernelId::colour_unpack, points, {&sorted_rgb, &planes}, p);
    Buffer sums = colour_plane_sums(dev, *runs, used, planes);
    lv[0].n = voxels;
    lv[0].keys = std::move(voxel_keys);
    lv[0].rgb = colour_alloc(dev, voxels * 4, "node colours");
    p.n = static_cast<uint32_t>(voxels);
    colour_dispatch(dev, KernelId::colour_level, voxels, {&sums, &lv[0].rgb}, p);
  }
  for (uint32_t l = 1; l <= levels; ++l) {
    ColourLevel& below = lv[l - 1];
    // (each level waits for its count anyway: waiting for the device here also frees what the level below retired)
    dev.finish();
    below.by_parent = segment_by_key(dev, below.keys, below.n, 3);  // siblings: at most 8 a run
    ColourLevel& level = lv[l];
    level.n = below.by_parent.count;
    level.keys = colour_alloc(dev, level.n * 8, "node codes");
    level.rgb = colour_alloc(dev, level.n * 4, "node colours");
    level.planes = colour_alloc(dev, kColourPlanes * level.n * 4, "colour planes");
    level.sizes = colour_alloc(dev, level.n * 4, "subtree sizes");
    MvColourParams p{};
    p.n = static_cast<uint32_t>(level.n);
    p.shift = 3;
    p.below = static_cast<uint32_t>(below.n);
    p.used = colour_planes_used(l - 1, voxels);
    p.leaf = l == 1 ? 1u : 0u;  // the voxels' colours stand for their planes
    colour_dispatch(dev, KernelId::colour_parents, level.n,
                    {&below.keys, l == 1 ? &below.rgb : &below.planes, &below.by_parent.starts, &level.keys,
                     &level.rgb, &level.planes, &level.sizes},
                    p);
    below.keys = Buffer();
    below.planes = Buffer();
  }
  if (lv[levels].n != 1) throw Error("voxel colours: the octree has " + std::to_string(lv[levels].n) + " roots");
  uint32_t entries32 = 0;
  dev.download(lv[levels].sizes, &entries32, 4);
  uint64_t entries = 0;
  for (const ColourLevel& level : lv) entries += level.n;
  // The root's size counts the nodes in 32 bits: it is exact only below 2^32.
  if (entries >= (uint64_t{1} << 32) || entries > kMaxDeviceItems)
    throw Error("voxel colours: " + std::to_string(entries) + " octree nodes, over the " +
                std::to_string(kMaxDeviceItems) + " one attribute array holds");
  if (entries32 != entries) throw Error("voxel colours: the root's subtree size disagrees with the node count");
  Buffer attributes = colour_alloc(dev, entries * 4, "depth-first colours");
  Buffer index = colour_alloc(dev, 4, "node indices");
  dev.fill(index, 0, 4);
  dev.copy(lv[levels].rgb, attributes, 4, 0, 0);
  dev.barrier();
  for (uint32_t l = levels; l >= 1; --l) {
    ColourLevel& below = lv[l - 1];
    Buffer below_index = colour_alloc(dev, below.n * 4, "node indices");
    MvColourParams p{};
    p.n = static_cast<uint32_t>(below.n);
    p.leaf = l == 1 ? 1u : 0u;  // voxels: size 1 each
    colour_dispatch(dev, KernelId::colour_place, below.n,
                    {&below.by_parent.e, &below.by_parent.starts, l == 1 ? &below.rgb : &below.sizes, &index,
                     &below.rgb, &below_index, &attributes},
                    p);
    index = std::move(below_index);
    lv[l] = ColourLevel();
  }
  dev.finish();
  std::vector<uint32_t> packed(entries);
  dev.download(attributes, packed.data(), entries * 4);
  std::vector<uint8_t> rgb(entries * 3);
  for (uint64_t i = 0; i < entries; ++i)
    for (int c = 0; c < 3; ++c) rgb[3 * i + c] = static_cast<uint8_t>(packed[i] >> (8 * c));
  return rgb;
}

}  // namespace

std::vector<uint8_t> depth_first_voxel_colours(Device& dev, Buffer voxel_keys, const Buffer& voxel_rgb, uint64_t voxels,
                                               uint32_t levels) {
  if (voxels == 0) return {};
  // one colour a voxel: no runs of points to find, so no point codes
  return depth_first_colours(dev, voxel_rgb, nullptr, voxels, std::move(voxel_keys), voxels, levels);
}

CloudVoxels voxelize_cloud(Device& dev, std::span<const uint32_t> cells, std::span<const uint32_t> rgb,
                           uint32_t levels, double* colour_seconds) {
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
  radix_sort(dev, keys, colour ? &values : nullptr, points, KeyBits::k64);
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
  const Segmentation runs = segment_by_key(dev, keys, points, 0);
  const uint64_t voxels = runs.count;
  Buffer unique = dev.alloc(voxels * 8, "voxel codes");
  MvColourParams first{};
  first.n = static_cast<uint32_t>(voxels);
  colour_dispatch(dev, KernelId::colour_parent_keys, voxels, {&keys, &runs.starts, &unique}, first);
  out.keys.resize(voxels);
  dev.download(unique, out.keys.data(), voxels * 8);
  keys = Buffer();  // the points' codes are done with: their runs and the voxels' codes stay
  {
    const auto start = std::chrono::steady_clock::now();
    out.colours = depth_first_colours(dev, values, &runs, points, std::move(unique), voxels, levels);
    if (colour_seconds) *colour_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return out;
}

}  // namespace mv
