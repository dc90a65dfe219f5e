// Host side of mesh colours (kernels/common/mesh_colour.h): the voxel set's bricks go up with each brick's first
// voxel, and the voxelizer's fragments in key order; a voxel whose brick's run of fragments is short takes its best
// fragment and colour in one work-item, a long run's voxels (or every voxel when the triangles need several
// batches) by three passes of atomic minima and then their colours per batch; the depth-first array comes from the
// cloud colours' bottom-up means and top-down placement.
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
#include "megavox/segmented.h"

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
// texels after it, in one buffer; each texture goes up from its own array.
Buffer upload_textures(Device& dev, const std::vector<io::MeshTexture>& textures) {
  std::vector<uint32_t> table(1 + 3 * textures.size());
  table[0] = static_cast<uint32_t>(textures.size());
  uint64_t words = table.size();
  for (size_t k = 0; k < textures.size(); ++k) {
    const io::MeshTexture& t = textures[k];
    if (t.rgb.size() != uint64_t{t.width} * t.height || t.rgb.empty()) throw Error("mesh colours: a texture of no texels");
    table[1 + 3 * k] = static_cast<uint32_t>(words);
    table[2 + 3 * k] = t.width;
    table[3 + 3 * k] = t.height;
    words += t.rgb.size();
    if (words * 4 > dev.info().max_binding_bytes)
      throw Error("mesh colours: the textures take " + format_bytes(words * 4) + ", over the " +
                  format_bytes(dev.info().max_binding_bytes) + " one device binding holds");
  }
  Buffer b = dev.alloc(words * 4, "mesh textures");
  dev.upload(b, table.data(), table.size() * 4);
  for (size_t k = 0; k < textures.size(); ++k)
    dev.upload(b, textures[k].rgb.data(), textures[k].rgb.size() * 4, uint64_t{table[1 + 3 * k]} * 4);
  return b;
}

// The fragments on the device in key order: as they are when one emission made them, else sorted there (the radix
// sort with their places as values, then their masks and triangles gathered in that order).
struct DeviceFragments {
  Buffer keys, masks, tris;
};
DeviceFragments upload_fragments(Device& dev, const Fragments& f) {
  const uint64_t n = f.size();
  DeviceFragments d{dev.alloc(n * 8, "colour fragment keys"), dev.alloc(n * 8, "colour fragment masks"),
                    dev.alloc(n * 4, "colour fragment triangles")};
  dev.upload(d.keys, f.keys.data(), n * 8);
  dev.upload(d.masks, f.masks.data(), n * 8);
  dev.upload(d.tris, f.tris.data(), n * 4);
  if (f.sorted) return d;
  const Buffer order = radix_sort_order(dev, d.keys, n);
  Buffer masks = dev.alloc(n * 8, "colour fragment masks");
  Buffer tris = dev.alloc(n * 4, "colour fragment triangles");
  gather_records(dev, d.masks, order, masks, n, 8);
  gather_records(dev, d.tris, order, tris, n, 4);
  dev.barrier();
  d.masks = std::move(masks);
  d.tris = std::move(tris);
  return d;
}

}  // namespace

MeshVoxelValues mesh_voxel_values(Device& dev, const Bricks& bricks, const Fragments& fragments,
                                  std::span<const float> tris, const MeshTriangleColours& colours,
                                  const std::vector<io::MeshTexture>& textures, uint64_t batch_triangles) {
  const uint64_t n_tris = tris.size() / 9;
  if (colours.rgb.size() != 3 * n_tris || colours.texture.size() != n_tris || colours.uv.size() != 6 * n_tris)
    throw Error("mesh colours: " + std::to_string(colours.rgb.size()) + " vertex colours for " +
                std::to_string(n_tris) + " triangles");
  if (fragments.masks.size() != fragments.size() || fragments.tris.size() != fragments.size())
    throw Error("mesh colours: fragments of unequal columns");
  const Buffer texels = upload_textures(dev, textures);
  const uint64_t voxels = bricks.voxels();
  MeshVoxelValues out;
  if (voxels == 0) return out;
  if (voxels >= UINT32_MAX / 3 || n_tris >= UINT32_MAX || bricks.size() >= UINT32_MAX ||
      fragments.size() >= UINT32_MAX)
    throw Error("mesh colours: " + std::to_string(voxels) + " voxels of " + std::to_string(n_tris) + " triangles (" +
                std::to_string(fragments.size()) + " fragments), past what one device call indexes");
  const auto nb = static_cast<uint32_t>(bricks.size());
  const auto nv = static_cast<uint32_t>(voxels);
  const auto nf = static_cast<uint32_t>(fragments.size());
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
  DeviceFragments frag = upload_fragments(dev, fragments);
  Buffer voxel_rgb = dev.alloc(uint64_t{nv} * 4, "voxel colours");
  Buffer voxel_keys = dev.alloc(uint64_t{nv} * 8, "voxel codes");
  Buffer voxel_brick = dev.alloc(uint64_t{nv} * 4, "voxel bricks");
  {
    MvVoxelizeParams p{};
    p.bricks = nb;
    dev.dispatch(dev.kernel(KernelId::mesh_voxel_keys), dev.groups_for(nb, kMeshColourLocal), kMeshColourLocal,
                 {&bkeys, &bmeta, &voxel_keys, &voxel_brick}, p);
    dev.barrier();
  }

  // Triangles (their floats and colour words) in batches a binding holds; a single batch (most meshes) goes up once
  // for every pass. With several, a brick's fragments may name triangles of different batches, so every run goes
  // through the passes.
  const uint64_t step = batch_triangles ? batch_triangles : mesh_batch_triangles(dev);
  const bool one_batch = n_tris <= step;
  struct Batch {
    Buffer tris, terms, attr;
  };
  auto upload_batch = [&](uint64_t first, uint64_t count, bool with_colours = true) {
    Batch b{dev.alloc(count * 36, "colour triangles"), dev.alloc(count * 8 * MV_MESH_TERMS, "colour triangle terms"),
            Buffer()};
    dev.upload(b.tris, tris.data() + 9 * first, count * 36);
    MvVoxelizeParams p{};
    p.batch_tris = static_cast<uint32_t>(count);
    dev.barrier();
    dev.dispatch(dev.kernel(KernelId::mesh_triangle_terms), dev.groups_for(count, kMeshColourLocal), kMeshColourLocal,
                 {&b.tris, &b.terms}, p);
    dev.barrier();
    if (!with_colours) return b;
    b.attr = dev.alloc(count * 4 * MV_MESH_ATTR_WORDS, "colour words");
    std::vector<uint32_t> attr(count * MV_MESH_ATTR_WORDS, 0);
    for (uint64_t k = 0; k < count; ++k) pack_colour_words(colours, first + k, &attr[k * MV_MESH_ATTR_WORDS]);
    dev.upload(b.attr, attr.data(), attr.size() * 4);
    return b;
  };
  Batch only = one_batch ? upload_batch(0, n_tris) : Batch();
  auto params = [&](uint64_t first, uint64_t count) {
    MvVoxelizeParams p{};
    p.bricks = nb;
    p.capacity = nv;
    p.tri_base = static_cast<uint32_t>(first);
    p.batch_tris = static_cast<uint32_t>(count);
    p.split_runs = one_batch ? 0u : 1u;
    return p;
  };
  // Whether any run is long (with several batches, every run is): then `best` holds the atomic minima.
  Kernel& pick = dev.kernel(KernelId::mesh_best_fragments);
  const uint32_t items = (nf + MV_MESH_FRAGMENTS_PER_ITEM - 1) / MV_MESH_FRAGMENTS_PER_ITEM;
  uint32_t long_runs = nf && !one_batch ? 1 : 0;
  Buffer best = dev.alloc(4, "long runs of fragments");
  if (one_batch && nf) {
    dev.upload(best, &long_runs, 4);
    MvVoxelizeParams p = params(0, n_tris);
    p.items = nf;
    dev.dispatch(pick, dev.groups_for(items, kMeshColourLocal), kMeshColourLocal,
                 {&only.tris, &only.terms, &frag.keys, &frag.masks, &frag.tris, &bkeys, &bmeta, &best, &best}, p);
    dev.download(best, &long_runs, 4);
  }
  if (long_runs) {
    best = dev.alloc(uint64_t{nv} * 12, "best fragments");
    dev.fill(best, 0xffffffffu, uint64_t{nv} * 12);
  }
  if (one_batch && nf) {  // the voxels of short runs, a work-item each: their best fragments and colours
    const Segmentation runs = segment_by_key(dev, frag.keys, nf);
    if (runs.count != nb)
      throw Error("internal error: mesh colours: " + std::to_string(runs.count) + " runs of fragments for " +
                  std::to_string(nb) + " bricks");
    MvVoxelizeParams p = params(0, n_tris);
    p.items = nv;
    p.colour_pass = long_runs;
    dev.dispatch(dev.kernel(KernelId::mesh_voxel_best_colours), dev.groups_for(nv, kMeshColourLocal),
                 kMeshColourLocal,
                 {&only.tris, &only.terms, &frag.masks, &frag.tris, &runs.starts, &voxel_keys, &voxel_brick,
                  &only.attr, &texels, &best, &voxel_rgb},
                 p);
    dev.barrier();
  }
  voxel_brick = Buffer();
  // The long runs: three passes, each over every batch (a pass must see them all before the next).
  for (uint32_t pass = 1; pass <= 3 && long_runs; ++pass)
    for (uint64_t first = 0; first < n_tris; first += step) {
      const uint64_t count = std::min(step, n_tris - first);
      Batch fresh = one_batch ? Batch() : upload_batch(first, count, false);
      Batch& t = one_batch ? only : fresh;
      MvVoxelizeParams p = params(first, count);
      p.items = nf;
      p.colour_pass = pass;
      dev.dispatch(pick, dev.groups_for(items, kMeshColourLocal), kMeshColourLocal,
                   {&t.tris, &t.terms, &frag.keys, &frag.masks, &frag.tris, &bkeys, &bmeta, &best, &best}, p);
      dev.barrier();
    }
  frag = {};
  if (!long_runs) {
    out.keys = std::move(voxel_keys);
    out.rgb = std::move(voxel_rgb);
    out.voxels = nv;
    return out;
  }

  // The triangle plane alone, then per batch the colours of the voxels of long runs whose triangle it holds.
  Buffer tri_plane = dev.alloc(uint64_t{nv} * 4, "voxel triangles");
  dev.copy(best, tri_plane, uint64_t{nv} * 4, uint64_t{nv} * 8, 0);
  dev.barrier();
  best = Buffer();
  for (uint64_t first = 0; first < n_tris; first += step) {
    const uint64_t count = std::min(step, n_tris - first);
    Batch fresh = one_batch ? Batch() : upload_batch(first, count);
    Batch& t = one_batch ? only : fresh;
    MvVoxelizeParams p = params(first, count);
    p.items = nv;
    dev.dispatch(dev.kernel(KernelId::mesh_voxel_colours), dev.groups_for(nv, kMeshColourLocal), kMeshColourLocal,
                 {&t.tris, &t.terms, &t.attr, &texels, &tri_plane, &voxel_keys, &voxel_rgb}, p);
    dev.barrier();
  }
  out.keys = std::move(voxel_keys);
  out.rgb = std::move(voxel_rgb);
  out.voxels = nv;
  return out;
}

std::vector<uint8_t> mesh_voxel_colours(Device& dev, const Bricks& bricks, const Fragments& fragments,
                                        std::span<const float> tris, const MeshTriangleColours& colours,
                                        uint32_t levels, uint64_t batch_triangles) {
  MeshVoxelValues v = mesh_voxel_values(dev, bricks, fragments, tris, colours, colours.textures, batch_triangles);
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
