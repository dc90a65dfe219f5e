// Host side of mesh colours (kernels/common/mesh_colour.h): the voxel set's bricks go up with each brick's first
// voxel; the voxelizer's walk runs three times over the triangles in batches a binding holds, each pass a
// 32-bit atomic minimum per voxel (distance high word, low word, triangle); then per batch the voxels whose
// triangle it holds take their colours; the depth-first array comes from the cloud colours' bottom-up means and
// top-down placement.
#include "voxel/mesh_colours.h"

#include <algorithm>
#include <bit>
#include <cstring>
#include <optional>
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

static_assert(kColourRecord == 9 + MV_MESH_ATTR_WORDS, "a coloured record: the triangle, then its colour words");

// Triangle t's colour words as the kernel reads them (MV_MESH_ATTR_WORDS): 3 vertex colours, 6 texture
// coordinates (float bits), the texture; the spare words are left as they are.
void pack_colour_words(const MeshTriangleColours& c, uint64_t t, uint32_t* words) {
  std::copy_n(&c.rgb[3 * t], 3, words);
  std::memcpy(words + 3, &c.uv[6 * t], 24);
  words[9] = c.texture[t];
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
  // batch the colours of the voxels whose triangle it holds. A batch's work items are found once; a single batch
  // (most meshes) goes up once for all four passes, several go up again for each.
  struct Batch {
    uint64_t first, count;
    WalkItems items;
  };
  struct Uploaded {
    Buffer tris, item_tri, item_col;
  };
  std::vector<Batch> batches;
  for (uint64_t first = 0, step = mesh_batch_triangles(dev); first < n_tris; first += step) {
    const uint64_t count = std::min(step, n_tris - first);
    batches.push_back({first, count, walk_items(tris.subspan(9 * first, 9 * count), resolution, box, box_size)});
  }
  auto upload_batch = [&](const Batch& b) {
    Uploaded u{dev.alloc(b.count * 36, "colour triangles"), dev.alloc(std::max<size_t>(b.items.tri.size(), 1) * 4, "colour work items"),
               dev.alloc(std::max<size_t>(b.items.col.size(), 1) * 4, "colour work items")};
    dev.upload(u.tris, tris.data() + 9 * b.first, b.count * 36);
    if (!b.items.tri.empty()) {
      dev.upload(u.item_tri, b.items.tri.data(), b.items.tri.size() * 4);
      dev.upload(u.item_col, b.items.col.data(), b.items.col.size() * 4);
    }
    return u;
  };
  std::optional<Uploaded> only;
  if (batches.size() == 1) only = upload_batch(batches[0]);
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
    for (const Batch& b : batches) {
      if (pass < 4 && b.items.tri.empty()) continue;
      Uploaded fresh;
      if (!only) fresh = upload_batch(b);
      Uploaded& u = only ? *only : fresh;
      MvVoxelizeParams p{};
      p.grid = resolution;
      p.columns_per_item = kVoxelizeColumnsPerItem;
      p.box_x = box[0];
      p.box_y = box[1];
      p.box_z = box[2];
      p.box_size = box_size;
      p.thin = rule == Voxelizer::Rule::kThin ? 1u : 0u;
      p.bricks = nb;
      p.tri_base = static_cast<uint32_t>(b.first);
      if (pass == 4) {
        std::vector<uint32_t> attr(b.count * MV_MESH_ATTR_WORDS, 0);
        for (uint64_t t = 0; t < b.count; ++t) pack_colour_words(colours, b.first + t, &attr[t * MV_MESH_ATTR_WORDS]);
        Buffer ab = dev.alloc(attr.size() * 4, "colour triangle attributes");
        dev.upload(ab, attr.data(), attr.size() * 4);
        p.items = nv;
        p.capacity = static_cast<uint32_t>(b.count);
        dev.dispatch(dev.kernel(KernelId::mesh_voxel_colours), dev.groups_for(nv, kMeshColourLocal), kMeshColourLocal,
                     {&u.tris, &ab, &texels, &tri_plane, &voxel_keys, &voxel_rgb}, p);
        dev.barrier();
        continue;
      }
      p.items = static_cast<uint32_t>(b.items.tri.size());
      p.capacity = nv;
      p.colour_pass = pass;
      dev.dispatch(walk, dev.groups_for(p.items, kMeshColourLocal), kMeshColourLocal,
                   {&u.tris, &u.item_tri, &u.item_col, &best, &bkeys, &bmeta}, p);
      dev.barrier();
    }
  }
  only.reset();
  tri_plane = Buffer();
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

void coloured_records(const std::vector<float>& tris, MeshTriangleColours& c, std::vector<float>& out) {
  const size_t n = tris.size() / 9;
  out.assign(n * kColourRecord, 0.0f);
  for (size_t t = 0; t < n; ++t) {
    float* r = &out[t * kColourRecord];
    std::copy_n(&tris[9 * t], 9, r);
    uint32_t words[MV_MESH_ATTR_WORDS] = {};
    pack_colour_words(c, t, words);
    words[10] = c.ordinal.at(t);
    std::memcpy(r + 9, words, sizeof words);
  }
  c.rgb.clear();
  c.uv.clear();
  c.texture.clear();
  c.ordinal.clear();
}

void split_records(std::vector<float>& records, MeshTriangleColours& c) {
  const size_t n = records.size() / kColourRecord;
  auto index_of = [&](size_t t) {
    uint32_t i = 0;
    std::memcpy(&i, &records[t * kColourRecord + 9 + 10], 4);
    return i;
  };
  std::vector<uint32_t> order(n);
  for (uint32_t t = 0; t < n; ++t) order[t] = t;
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return index_of(a) < index_of(b); });
  std::vector<float> tris(9 * n);
  for (size_t k = 0; k < n; ++k) {
    const float* r = &records[size_t{order[k]} * kColourRecord];
    std::copy_n(r, 9, &tris[9 * k]);
    uint32_t words[MV_MESH_ATTR_WORDS];
    std::memcpy(words, r + 9, sizeof words);
    c.rgb.insert(c.rgb.end(), words, words + 3);
    float uv[6];
    std::memcpy(uv, words + 3, 24);
    c.uv.insert(c.uv.end(), uv, uv + 6);
    c.texture.push_back(words[9]);
  }
  records = std::move(tris);
}

std::vector<uint8_t> cube_colours_depth_first(Device& dev, const std::string& input, std::vector<uint64_t>& keys,
                                              std::vector<uint32_t>& rgb, uint32_t levels) {
  const uint64_t n = keys.size();
  if (n == 0) return {};
  try {
    Buffer kb = dev.alloc(n * 8, "cube voxel codes");
    Buffer vb = dev.alloc(n * 4, "cube voxel colours");
    dev.upload(kb, keys.data(), n * 8);
    dev.upload(vb, rgb.data(), n * 4);
    std::vector<uint64_t>().swap(keys);
    std::vector<uint32_t>().swap(rgb);
    dev.barrier();
    radix_sort(dev, kb, &vb, n, KeyBits::k64);
    dev.barrier();
    return depth_first_voxel_colours(dev, std::move(kb), vb, n, levels);
  } catch (const DeviceMemoryError& e) {  // not retried in smaller cubes: this step holds every voxel at once
    throw CodedError(ErrorCode::out_of_memory,
                     input + ": the voxel colours of " + std::to_string(n) +
                         " voxels do not fit device memory (" + e.what() +
                         "): raise --device-memory, lower the resolution, or build without colours (--attributes none)",
                     setting_device_memory | setting_none);
  }
}

}  // namespace mv
