// Host side of the surface voxelizer (kernel body: kernels/common/voxelize.h).
#include "common/voxelize.h"

#include "megavox/voxelize.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <utility>

#include "megavox/error.h"
#include "megavox/primitives.h"
#include "common/dag.h"

namespace mv {

namespace {
constexpr uint32_t kColumnsPerItem = kVoxelizeColumnsPerItem;
}

WalkItems walk_items(std::span<const float> tris, uint32_t resolution, const uint32_t box[3], uint32_t box_size) {
  // Work items: runs of at most kColumnsPerItem brick columns of each triangle's walk, with an estimate of
  // their bricks (two a column: the plane crosses most columns of its bounding box in one or two layers, and
  // misses many) that sizes the output; a run that finds more is emitted again with room for all.
  WalkItems w;
  const size_t count = tris.size() / 9;
  for (uint32_t t = 0; t < count; ++t) {
    const float* v = &tris[9 * size_t{t}];
    MvTriFrame f = mv_tri_frame(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], resolution, box[0], box[1],
                                box[2], box_size);
    if (f.empty) continue;
    const uint64_t columns = mv_frame_columns(f);
    for (uint64_t c = 0; c < columns; c += kColumnsPerItem) {
      w.tri.push_back(t);
      w.col.push_back(static_cast<uint32_t>(c));
      w.guess.push_back(2 * static_cast<uint32_t>(std::min<uint64_t>(kColumnsPerItem, columns - c)));
    }
  }
  if (w.tri.size() > kMaxDeviceItems) throw Error("voxelize: too many work items in one batch");
  return w;
}

GridPlacement parse_grid_origin(const std::string& text) {
  GridPlacement p;
  if (text == "center") p.origin = GridPlacement::Origin::kCenter;
  else if (text == "min") p.origin = GridPlacement::Origin::kMin;
  else throw CodedError(ErrorCode::invalid_argument, "grid origin '" + text + "': choose center or min (or give the bounds)",
                        setting_grid_origin | setting_bounds);
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
      throw CodedError(ErrorCode::invalid_argument,
                       "bounds '" + text + "' are not X,Y,Z,SIZE (the cube's min corner and side, four numbers)",
                       setting_bounds);
    s = end + 1;
  }
  if (!(v[3] > 0))
    throw CodedError(ErrorCode::invalid_argument, "bounds '" + text + "': the cube's side must be positive", setting_bounds);
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
                       size_t triangles, std::vector<float>& out, bool clip, std::vector<uint32_t>* kept) {
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
    if (kept) kept->push_back(static_cast<uint32_t>(t));
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

  const WalkItems w = walk_items(tris, resolution_, box_, box_size_);
  const std::vector<uint32_t>& item_tri = w.tri;
  const std::vector<uint32_t>& item_col = w.col;
  const std::vector<uint32_t>& item_guess = w.guess;
  const auto items = static_cast<uint32_t>(item_tri.size());
  if (items == 0) return;
  if (record_ && triangles_ >= UINT32_MAX)
    throw Error("voxelize: " + std::to_string(triangles_) + " triangles, past the 2^32 - 1 a fragment indexes");
  Emission e{dev_.alloc(tris.size() * 4, "voxelizer triangles"), dev_.alloc(uint64_t{items} * 4, "voxelizer work items"),
             dev_.alloc(uint64_t{items} * 4, "voxelizer work items"), dev_.alloc(4, "voxelizer brick counter"),
             static_cast<uint32_t>(triangles_ - count)};
  dev_.upload(e.tris, tris.data(), tris.size() * 4);
  dev_.upload(e.item_tri, item_tri.data(), uint64_t{items} * 4);
  dev_.upload(e.item_col, item_col.data(), uint64_t{items} * 4);

  // Bricks in flight: keys and masks (8 + 8 bytes), the sort's order and scratch (8 + 4 + 4), the gathered
  // masks (8): 40 bytes each, and recording fragments their triangles before and after the gather (4 + 4); half
  // the free memory, for the sort's slack.
  const uint64_t each = record_ ? 48 : 40;
  const uint64_t room = std::min((dev_.memory_budget() - dev_.memory_used()) / 2 / each, kMaxDeviceItems);
  if (room == 0) throw Error("voxelize: no device memory left for voxel bricks");
  for (uint32_t first = 0; first < items;) {
    uint64_t guess = 0;
    uint32_t last = first;
    while (last < items && (last == first || guess + item_guess[last] <= room)) guess += item_guess[last++];
    emit(e, first, last, std::clamp<uint64_t>(guess, 1024, room), room);
    first = last;
  }
  dev_.finish();
}

// Items [first, last) into at most `capacity` bricks; past it, again with room for the count found, or split
// in halves when that is more than `room`.
void Voxelizer::emit(Emission& e, uint32_t first, uint32_t last, uint64_t capacity, uint64_t room) {
  const uint32_t local = 64, zero = 0;
  Buffer keys = dev_.alloc(capacity * 8, "voxel brick keys");
  Buffer masks = dev_.alloc(capacity * 8, "voxel brick masks");
  Buffer slot_tris = dev_.alloc(record_ ? capacity * 4 : 4, "voxel brick triangles");
  dev_.upload(e.counter, &zero, 4);
  MvVoxelizeParams p{};
  p.first_item = first;
  p.items = last - first;
  p.grid = resolution_;
  p.columns_per_item = kColumnsPerItem;
  p.capacity = static_cast<uint32_t>(capacity);
  p.box_size = box_size_;
  p.box_x = box_[0];
  p.box_y = box_[1];
  p.box_z = box_[2];
  p.thin = rule_ == Rule::kThin ? 1u : 0u;
  p.tri_base = e.first_tri;
  p.record_tris = record_ ? 1u : 0u;
  dev_.dispatch(dev_.kernel(KernelId::voxelize), dev_.groups_for(last - first, local), local,
                {&e.tris, &e.item_tri, &e.item_col, &e.counter, &keys, &masks, &slot_tris}, p);
  uint32_t found = 0;
  dev_.download(e.counter, &found, 4);
  if (found > capacity) {
    keys = Buffer();
    masks = Buffer();
    slot_tris = Buffer();
    if (found <= room) return emit(e, first, last, found, room);
    if (last - first == 1) throw Error("voxelize: one work item meets more bricks than device memory holds");
    const uint32_t mid = first + (last - first) / 2;
    emit(e, first, mid, capacity, room);
    emit(e, mid, last, capacity, room);
    return;
  }
  hits_ += found;
  if (found == 0) return;
  // Sort the keys with their slots, gather the masks in that order; repeats are OR-ed on the host (a brick
  // meets a few triangles at most, so there are few).
  const Buffer order = radix_sort_order(dev_, keys, found);
  Buffer sorted = dev_.alloc(uint64_t{found} * 8, "sorted brick masks");
  const MvDagParams g{found, 0, 0, 0, 0, 0};
  dev_.dispatch(dev_.kernel(KernelId::brick_gather), dev_.groups_for(found, local), local, {&masks, &order, &sorted}, g);
  std::vector<uint64_t> hk(found), hm(found);
  dev_.download(keys, hk.data(), uint64_t{found} * 8);
  dev_.download(sorted, hm.data(), uint64_t{found} * 8);
  if (record_) keep_fragments(hk, hm, slot_tris, order, found);
  Bricks chunk;
  append_or_merged(hk, hm, chunk);
  merge(std::move(chunk));
}

void Voxelizer::keep_fragments(const std::vector<uint64_t>& keys, const std::vector<uint64_t>& masks,
                               const Buffer& slot_tris, const Buffer& order, uint32_t found) {
  Buffer tris = dev_.alloc(uint64_t{found} * 4, "sorted brick triangles");
  gather_records(dev_, slot_tris, order, tris, found, 4);
  const size_t at = fragments_.size();
  fragments_.sorted = fragments_.sorted && at == 0;
  fragments_.keys.insert(fragments_.keys.end(), keys.begin(), keys.end());
  fragments_.masks.insert(fragments_.masks.end(), masks.begin(), masks.end());
  fragments_.tris.resize(at + found);
  dev_.download(tris, fragments_.tris.data() + at, uint64_t{found} * 4);
}

void Voxelizer::merge(Bricks&& chunk) {
  // the merge holds the old bricks, the chunk and the union at once, beside the fragments kept
  const uint64_t need = 16 * (2 * (bricks_.size() + chunk.size())) + 20 * fragments_.size();
  if (host_budget_ && need > host_budget_)
    throw CodedError(ErrorCode::out_of_memory,
                     "voxelize: the voxel bricks need " + format_bytes(need) + " of host memory, over the " +
                         format_bytes(host_budget_) +
                         " of the host memory budget left for them; raise the host memory budget, or lower the cube "
                         "size so the build runs out of core in smaller cubes",
                     setting_host_memory | setting_cube);
  if (bricks_.empty()) {
    bricks_ = std::move(chunk);
    return;
  }
  bricks_ = merge_bricks(bricks_, chunk);
}

Bricks Voxelizer::take_bricks() { return std::exchange(bricks_, {}); }

}  // namespace mv
