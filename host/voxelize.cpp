// Host side of the surface voxelizer (kernel body: kernels/common/voxelize.h).
#include "../kernels/common/voxelize.h"

#include "megavox/voxelize.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <utility>

#include "megavox/error.h"
#include "megavox/primitives.h"

namespace mv {

namespace {
constexpr uint32_t kColumnsPerItem = 256;
}

void Bounds::extend(double x, double y, double z) {
  const double p[3] = {x, y, z};
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::min(lo[a], p[a]);
    hi[a] = std::max(hi[a], p[a]);
  }
}

GridPlacement parse_grid_origin(const std::string& text) {
  GridPlacement p;
  if (text == "center") p.origin = GridPlacement::Origin::kCenter;
  else if (text == "min") p.origin = GridPlacement::Origin::kMin;
  else throw Error("--grid-origin '" + text + "': choose center or min (or give --bounds X,Y,Z,SIZE)");
  return p;
}

GridPlacement parse_grid_bounds(const std::string& text) {
  GridPlacement p;
  p.origin = GridPlacement::Origin::kCube;
  double v[4];
  const char* s = text.c_str();
  for (int i = 0; i < 4; ++i) {
    char* end = nullptr;
    v[i] = std::strtod(s, &end);
    const char want = i < 3 ? ',' : '\0';
    if (end == s || *end != want || !std::isfinite(v[i]))
      throw Error("--bounds '" + text + "' is not X,Y,Z,SIZE (the cube's min corner and side, four numbers)");
    s = end + 1;
  }
  if (!(v[3] > 0)) throw Error("--bounds '" + text + "': the cube's side must be positive");
  for (int a = 0; a < 3; ++a) p.corner[a] = v[a];
  p.side = v[3];
  return p;
}

std::string to_string(GridPlacement::Origin origin) {
  switch (origin) {
    case GridPlacement::Origin::kCenter: return "center";
    case GridPlacement::Origin::kMin: return "min";
    case GridPlacement::Origin::kCube: return "bounds";
  }
  return "?";
}

GridTransform grid_for_bounds(const Bounds& b, uint32_t resolution, const GridPlacement& placement) {
  if (resolution == 0 || resolution > (1u << 21))
    throw Error("resolution " + std::to_string(resolution) + " is outside [1, 2097152] voxels per axis");
  GridTransform g;
  g.resolution = resolution;
  if (placement.origin == GridPlacement::Origin::kCube) {
    if (!(placement.side > 0) || !std::isfinite(placement.side)) throw Error("the grid's cube needs a positive side");
    for (int a = 0; a < 3; ++a) g.origin[a] = placement.corner[a];
    g.voxel_size = placement.side / resolution;
    return g;
  }
  if (b.empty()) throw Error("cannot place a grid around an empty model");
  double side = 0;
  for (int a = 0; a < 3; ++a) side = std::max(side, b.hi[a] - b.lo[a]);
  if (!(side > 0)) side = 1;
  const bool centre = placement.origin == GridPlacement::Origin::kCenter;
  for (int a = 0; a < 3; ++a) g.origin[a] = centre ? 0.5 * (b.lo[a] + b.hi[a]) - 0.5 * side : b.lo[a];
  g.voxel_size = side / resolution;
  return g;
}

void triangles_to_grid(const GridTransform& grid, std::span<const float> positions, const uint32_t* indices,
                       size_t triangles, std::vector<float>& out, bool clip) {
  const double n = grid.resolution;
  const double inv = 1.0 / grid.voxel_size;
  const size_t vertices = positions.size() / 3;
  out.reserve(out.size() + triangles * 9);
  for (size_t t = 0; t < triangles; ++t) {
    float g[9];
    bool outside[3][2] = {{true, true}, {true, true}, {true, true}};  // [axis][below, above] for all vertices
    for (int k = 0; k < 3; ++k) {
      uint32_t v = indices[3 * t + k];
      if (v >= vertices)
        throw Error("triangle " + std::to_string(t) + " refers to vertex " + std::to_string(v) + " of " +
                    std::to_string(vertices));
      for (int a = 0; a < 3; ++a) {
        double x = (double(positions[3 * size_t{v} + a]) - grid.origin[a]) * inv;
        if (!clip) x = std::clamp(x, 0.0, n);
        g[3 * k + a] = static_cast<float>(x);
        outside[a][0] = outside[a][0] && g[3 * k + a] < 0;
        outside[a][1] = outside[a][1] && g[3 * k + a] > n;
      }
    }
    bool misses = false;
    for (int a = 0; a < 3; ++a) misses = misses || outside[a][0] || outside[a][1];
    if (clip && misses) continue;
    out.insert(out.end(), g, g + 9);
  }
}

Voxelizer::Voxelizer(Device& dev, uint32_t resolution, Rule rule)
    : dev_(dev), resolution_(resolution), rule_(rule), box_size_(resolution) {
  if (resolution == 0 || resolution > (1u << 21))
    throw Error("resolution " + std::to_string(resolution) + " is outside [1, 2097152] voxels per axis");
}

void Voxelizer::restrict_to(uint32_t x, uint32_t y, uint32_t z, uint32_t size) {
  box_[0] = x;
  box_[1] = y;
  box_[2] = z;
  box_size_ = size;
}

void Voxelizer::add(const std::vector<float>& tris) {
  const size_t count = tris.size() / 9;
  if (count == 0) return;
  if (count > UINT32_MAX / 9) throw Error("voxelize: too many triangles in one batch");
  triangles_ += count;

  // Work items: runs of at most kColumnsPerItem columns of each triangle's walk.
  std::vector<uint32_t> item_tri, item_col;
  for (uint32_t t = 0; t < count; ++t) {
    const float* v = &tris[9 * size_t{t}];
    MvTriFrame f = mv_tri_frame(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], resolution_, box_[0], box_[1],
                                box_[2], box_size_);
    if (f.empty) continue;
    uint64_t columns = uint64_t{mv_frame_hi(f, f.u) - mv_frame_lo(f, f.u) + 1} *
                       (mv_frame_hi(f, f.v) - mv_frame_lo(f, f.v) + 1);
    if (columns > UINT32_MAX - kColumnsPerItem) throw Error("voxelize: triangle " + std::to_string(t) + " is too large");
    for (uint64_t c = 0; c < columns; c += kColumnsPerItem) {
      item_tri.push_back(t);
      item_col.push_back(static_cast<uint32_t>(c));
    }
  }
  const auto items = static_cast<uint32_t>(item_tri.size());
  if (items == 0) return;
  Buffer tri_buf = dev_.alloc(tris.size() * 4, "voxelizer triangles");
  Buffer tri_of = dev_.alloc(uint64_t{items} * 4, "voxelizer work items");
  Buffer col_of = dev_.alloc(uint64_t{items} * 4, "voxelizer work items");
  Buffer counts = dev_.alloc(uint64_t{items} * 4, "voxelizer counts");
  dev_.upload(tri_buf, tris.data(), tris.size() * 4);
  dev_.upload(tri_of, item_tri.data(), uint64_t{items} * 4);
  dev_.upload(col_of, item_col.data(), uint64_t{items} * 4);

  Kernel& k = dev_.kernel(KernelId::voxelize);
  const uint32_t thin = rule_ == Rule::kThin ? 1u : 0u;
  const uint32_t local = 64;
  MvVoxelizeParams p{0, items, resolution_, kColumnsPerItem, 0, box_size_, box_[0], box_[1], box_[2], thin};
  Buffer none;
  dev_.dispatch(k, dev_.groups_for(items, local), local, {&tri_buf, &tri_of, &col_of, &counts, &none}, p);
  std::vector<uint32_t> n(items);
  dev_.download(counts, n.data(), uint64_t{items} * 4);

  // Emit in chunks of items whose keys (with sort scratch and unique output: 4 copies) fit the budget.
  const uint64_t room = (dev_.memory_budget() - dev_.memory_used()) / 2 / (4 * 8);
  if (room == 0) throw Error("voxelize: no device memory left for voxel keys");
  std::vector<uint32_t> offsets(items);
  uint32_t first = 0;
  while (first < items) {
    uint64_t total = 0;
    uint32_t last = first;
    while (last < items && (last == first || total + n[last] <= std::min(room, kMaxDeviceItems))) {
      offsets[last] = static_cast<uint32_t>(total);
      total += n[last++];
    }
    if (total > kMaxDeviceItems) throw Error("voxelize: one work item hits more than 2^31 voxels");
    hits_ += total;
    if (total > 0) {
      dev_.upload(counts, offsets.data() + first, uint64_t{last - first} * 4, uint64_t{first} * 4);
      Buffer keys = dev_.alloc(total * 8, "voxel keys");
      p = {first, last - first, resolution_, kColumnsPerItem, 1, box_size_, box_[0], box_[1], box_[2], thin};
      dev_.dispatch(k, dev_.groups_for(last - first, local), local, {&tri_buf, &tri_of, &col_of, &counts, &keys}, p);
      dev_.barrier();
      radix_sort(dev_, keys, nullptr, total, KeyBits::k64);
      Buffer unique = dev_.alloc(total * 8, "unique voxel keys");
      uint64_t m = unique_sorted(dev_, keys, unique, total);
      std::vector<uint64_t> chunk(m);
      dev_.download(unique, chunk.data(), m * 8);
      merge(std::move(chunk));
    }
    first = last;
  }
  dev_.finish();
}

void Voxelizer::merge(std::vector<uint64_t>&& chunk) {
  // the merge holds the old keys, the chunk and the union at once
  const uint64_t need = 8 * (2 * (keys_.size() + chunk.size()));
  if (host_budget_ && need > host_budget_)
    throw Error("voxelize: the voxel keys need " + std::to_string((need + (1 << 20) - 1) >> 20) +
                " MiB of host memory, over --memory " + std::to_string(host_budget_ >> 20) +
                " MiB; raise --memory, or lower --cube so the build runs out of core in smaller cubes");
  if (keys_.empty()) {
    keys_ = std::move(chunk);
    return;
  }
  std::vector<uint64_t> merged;
  merged.reserve(keys_.size() + chunk.size());
  std::set_union(keys_.begin(), keys_.end(), chunk.begin(), chunk.end(), std::back_inserter(merged));
  keys_.swap(merged);
}

std::vector<uint64_t> Voxelizer::take_keys() { return std::exchange(keys_, {}); }

}  // namespace mv
