// Host side of mesh colours (kernels/common/mesh_colour.h): the voxel set's bricks go up with each brick's first
// voxel; the voxelizer's walk runs three times over the triangles in batches a binding holds, each pass a
// 32-bit atomic minimum per voxel (distance high word, low word, triangle); then per batch the voxels whose
// triangle it holds take their colours; the depth-first array comes from the cloud colours' bottom-up means and
// top-down placement.
#include "voxel/mesh_colours.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <string>

#include "common/voxelize.h"
#include "megavox/colour.h"
#include "megavox/error.h"
#include "megavox/primitives.h"

namespace mv {

namespace {

constexpr uint32_t kMeshColourLocal = 64;

// Triangles per batch of the walk: their floats and work items within one binding.
uint64_t mesh_batch_triangles(const Device& dev) {
  const uint64_t binding = std::max<uint64_t>(dev.info().max_binding_bytes, 1 << 20);
  return std::max<uint64_t>(1, std::min<uint64_t>(binding / 36, uint64_t{1} << 24));
}

// The textures as the kernel samples them: a table (the count, then offset, width, height per texture) and the
// texels after it, in one buffer.
Buffer upload_textures(Device& dev, const std::vector<io::MeshTexture>& textures) {
  std::vector<uint32_t> words(1 + 3 * textures.size());
  words[0] = static_cast<uint32_t>(textures.size());
  for (size_t k = 0; k < textures.size(); ++k) {
    const io::MeshTexture& t = textures[k];
    if (t.rgb.size() != uint64_t{t.width} * t.height || t.rgb.empty()) throw Error("mesh colours: a texture of no texels");
    words[1 + 3 * k] = static_cast<uint32_t>(words.size());
    words[2 + 3 * k] = t.width;
    words[3 + 3 * k] = t.height;
    words.insert(words.end(), t.rgb.begin(), t.rgb.end());
    if (words.size() * 4 > dev.info().max_binding_bytes)
      throw Error("mesh colours: the textures take " + format_bytes(words.size() * 4) + ", over the " +
                  format_bytes(dev.info().max_binding_bytes) + " one device binding holds");
  }
  Buffer b = dev.alloc(words.size() * 4, "mesh textures");
  dev.upload(b, words.data(), words.size() * 4);
  return b;
}

}  // namespace

MeshVoxelValues mesh_voxel_values(Device& dev, const Bricks& bricks, std::span<const float> tris,
                                  const MeshTriangleColours& colours, const std::vector<io::MeshTexture>& textures,
                                  uint32_t resolution, Voxelizer::Rule rule, const uint32_t box[3], uint32_t box_size) {
  const uint64_t n_tris = tris.size() / 9;
  if (colours.rgb.size() != 3 * n_tris || colours.texture.size() != n_tris || colours.uv.size() != 6 * n_tris)
    throw Error("mesh colours: " + std::to_string(colours.rgb.size()) + " vertex colours for " +
                std::to_string(n_tris) + " triangles");
  const Buffer texels = upload_textures(dev, textures);
  const uint64_t voxels = bricks.voxels();
  MeshVoxelValues out;
  if (voxels == 0) return out;
  if (voxels >= UINT32_MAX / 3 || n_tris >= UINT32_MAX || bricks.size() >= UINT32_MAX)
    throw Error("mesh colours: " + std::to_string(voxels) + " voxels of " + std::to_string(n_tris) +
                " triangles, past what one device call indexes");
  const auto nb = static_cast<uint32_t>(bricks.size());
  const auto nv = static_cast<uint32_t>(voxels);
  std::vector<uint64_t> meta(2 * uint64_t{nb});
  for (uint64_t b = 0, at = 0; b < nb; ++b) {
    meta[2 * b] = bricks.masks[b];
    meta[2 * b + 1] = at;
    at += std::popcount(bricks.masks[b]);
  }
  Buffer bkeys = dev.alloc(uint64_t{nb} * 8, "colour bricks");
  dev.upload(bkeys, bricks.keys.data(), uint64_t{nb} * 8);
  Buffer bmeta = dev.alloc(uint64_t{nb} * 16, "colour brick voxels");
  dev.upload(bmeta, meta.data(), meta.size() * 8);
  meta = {};
  Buffer best = dev.alloc(uint64_t{nv} * 12, "best fragments");
  dev.fill(best, 0xffffffffu, uint64_t{nv} * 12);
  Kernel& walk = dev.kernel(KernelId::mesh_colour_walk);

  // The three passes, each over every batch of triangles (a pass must see them all before the next), then per
  // batch the colours of the voxels whose triangle it holds.
  const uint64_t batch = mesh_batch_triangles(dev);
  Buffer voxel_keys = dev.alloc(uint64_t{nv} * 8, "voxel codes");
  Buffer voxel_rgb = dev.alloc(uint64_t{nv} * 4, "voxel colours");
  Buffer tri_plane;
  for (uint32_t pass = 1; pass <= 4; ++pass) {
    if (pass == 4) {  // the triangle plane alone, and the voxels' keys
      tri_plane = dev.alloc(uint64_t{nv} * 4, "voxel triangles");
      dev.copy(best, tri_plane, uint64_t{nv} * 4, uint64_t{nv} * 8, 0);
      dev.barrier();
      best = Buffer();
      MvVoxelizeParams p{};
      p.bricks = nb;
      dev.dispatch(dev.kernel(KernelId::mesh_voxel_keys), dev.groups_for(nb, kMeshColourLocal), kMeshColourLocal,
                   {&bkeys, &bmeta, &voxel_keys}, p);
      dev.barrier();
    }
    for (uint64_t first = 0; first < n_tris; first += batch) {
      const uint64_t count = std::min(batch, n_tris - first);
      const std::span<const float> slice = tris.subspan(9 * first, 9 * count);
      Buffer tb = dev.alloc(count * 36, "colour triangles");
      dev.upload(tb, slice.data(), count * 36);
      MvVoxelizeParams p{};
      p.grid = resolution;
      p.columns_per_item = kVoxelizeColumnsPerItem;
      p.box_x = box[0];
      p.box_y = box[1];
      p.box_z = box[2];
      p.box_size = box_size;
      p.thin = rule == Voxelizer::Rule::kThin ? 1u : 0u;
      p.bricks = nb;
      p.tri_base = static_cast<uint32_t>(first);
      if (pass == 4) {
        std::vector<uint32_t> attr(count * MV_MESH_ATTR_WORDS, 0);
        for (uint64_t t = 0; t < count; ++t) {
          uint32_t* a = &attr[t * MV_MESH_ATTR_WORDS];
          std::copy_n(&colours.rgb[3 * (first + t)], 3, a);
          std::memcpy(a + 3, &colours.uv[6 * (first + t)], 24);
          a[9] = colours.texture[first + t];
        }
        Buffer ab = dev.alloc(attr.size() * 4, "colour triangle attributes");
        dev.upload(ab, attr.data(), attr.size() * 4);
        p.items = nv;
        p.capacity = static_cast<uint32_t>(count);
        dev.dispatch(dev.kernel(KernelId::mesh_voxel_colours), dev.groups_for(nv, kMeshColourLocal), kMeshColourLocal,
                     {&tb, &ab, &texels, &tri_plane, &voxel_keys, &voxel_rgb}, p);
        dev.barrier();
        continue;
      }
      const WalkItems w = walk_items(slice, resolution, box, box_size);
      if (w.tri.empty()) continue;
      Buffer it = dev.alloc(w.tri.size() * 4, "colour work items");
      Buffer ic = dev.alloc(w.col.size() * 4, "colour work items");
      dev.upload(it, w.tri.data(), w.tri.size() * 4);
      dev.upload(ic, w.col.data(), w.col.size() * 4);
      p.items = static_cast<uint32_t>(w.tri.size());
      p.capacity = nv;
      p.colour_pass = pass;
      dev.dispatch(walk, dev.groups_for(p.items, kMeshColourLocal), kMeshColourLocal, {&tb, &it, &ic, &best, &bkeys, &bmeta},
                   p);
      dev.barrier();
    }
  }
  out.keys = std::move(voxel_keys);
  out.rgb = std::move(voxel_rgb);
  out.voxels = nv;
  return out;
}

std::vector<uint8_t> mesh_voxel_colours(Device& dev, const Bricks& bricks, std::span<const float> tris,
                                        const MeshTriangleColours& colours, uint32_t levels, Voxelizer::Rule rule) {
  const uint32_t resolution = 1u << levels, box[3] = {0, 0, 0};
  MeshVoxelValues v = mesh_voxel_values(dev, bricks, tris, colours, colours.textures, resolution, rule, box, resolution);
  if (v.voxels == 0) return {};
  return depth_first_voxel_colours(dev, std::move(v.keys), v.rgb, v.voxels, levels);
}

}  // namespace mv
