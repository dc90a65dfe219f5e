#include "point_kernels.h"

#include "common/points.h"

#include <algorithm>
#include <bit>
#include <limits>

#include "primitives/chunking.h"
#include "huge_pages.h"
#include "megavox/error.h"
#include "megavox/primitives.h"
#include "timing.h"

#include <chrono>

namespace mv::points {

PointCube cube_of(std::span<const int32_t> xyz) {
  PointCube cube;
  if (xyz.empty()) return cube;
  int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = hi[a] = xyz[a];
  for (size_t i = 0; i < xyz.size(); i += 3)
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min<int64_t>(lo[a], xyz[i + a]);
      hi[a] = std::max<int64_t>(hi[a], xyz[i + a]);
    }
  return cube_of_bounds(lo, hi);
}

PointCube cube_of_bounds(const int64_t lo[3], const int64_t hi[3]) {
  PointCube cube;
  uint64_t extent = 0;
  for (int a = 0; a < 3; ++a) {
    cube.min[a] = lo[a];
    extent = std::max<uint64_t>(extent, static_cast<uint64_t>(hi[a] - lo[a]));
  }
  // The largest offset, extent, must land in cell 2^21 - 1 or below.
  const uint32_t width = static_cast<uint32_t>(std::bit_width(extent));
  cube.shift = static_cast<int32_t>(width) - 21;
  return cube;
}

void point_bounds(Device& dev, std::span<const int32_t> xyz, int64_t lo[3], int64_t hi[3]) {
  const uint64_t n = xyz.size() / 3;
  if (n == 0) throw Error("points: the bounds of no points");
  constexpr uint32_t kLocal = 64;
  constexpr uint64_t kMaxItems = uint64_t{1} << 15;  // partial boxes per chunk: 768 KiB, reduced on the host
  const uint64_t chunk = std::min<uint64_t>({n, uint64_t{1} << 23, detail::device_chunk(dev, "point_bounds", 12, 12)});
  Buffer xb = dev.alloc(chunk * 12, "point coordinates");
  const uint32_t groups = dev.groups_for(std::min<uint64_t>(chunk, kMaxItems), kLocal);
  const uint64_t items = uint64_t{groups} * kLocal;
  Buffer pb = dev.alloc(items * 24, "point bounds");
  std::vector<uint32_t> partial(items * 6);
  uint32_t box[6] = {UINT32_MAX, UINT32_MAX, UINT32_MAX, 0, 0, 0};  // sign-flipped bits, as the kernel keeps them
  for (uint64_t first = 0; first < n; first += chunk) {
    const uint64_t m = std::min(chunk, n - first);
    dev.upload(xb, xyz.data() + 3 * first, m * 12);
    MvPointParams p{};
    p.n = static_cast<uint32_t>(m);
    dev.dispatch(dev.kernel(KernelId::point_bounds), groups, kLocal, {&xb, &pb}, p);
    dev.barrier();
    dev.download(pb, partial.data(), items * 24);
    for (uint64_t i = 0; i < items; ++i)
      for (int a = 0; a < 3; ++a) {
        box[a] = std::min(box[a], partial[6 * i + a]);
        box[3 + a] = std::max(box[3 + a], partial[6 * i + 3 + a]);
      }
  }
  for (int a = 0; a < 3; ++a) {
    lo[a] = static_cast<int32_t>(box[a] ^ 0x80000000u);
    hi[a] = static_cast<int32_t>(box[3 + a] ^ 0x80000000u);
  }
}

PointCube cube_on_device(Device& dev, std::span<const int32_t> xyz) {
  if (xyz.empty()) return PointCube{};
  int64_t lo[3], hi[3];
  point_bounds(dev, xyz, lo, hi);
  return cube_of_bounds(lo, hi);
}

namespace {

// One point_codes dispatch: points [first, first + m) of the cloud through the coordinates' buffer xb, their
// codes and indices written to keys and values from position `out` on.
void dispatch_codes(Device& dev, Buffer& xb, std::span<const int32_t> xyz, const PointCube& cube, uint64_t first,
                    uint64_t m, Buffer& keys, Buffer& values, uint64_t out) {
  dev.upload(xb, xyz.data() + 3 * first, m * 12);
  MvPointParams p{};
  p.n = static_cast<uint32_t>(m);
  p.shift = cube.shift > 0 ? static_cast<uint32_t>(cube.shift) : 0;
  p.lshift = cube.shift < 0 ? static_cast<uint32_t>(-cube.shift) : 0;
  p.min_x = static_cast<uint32_t>(static_cast<int32_t>(cube.min[0]));
  p.min_y = static_cast<uint32_t>(static_cast<int32_t>(cube.min[1]));
  p.min_z = static_cast<uint32_t>(static_cast<int32_t>(cube.min[2]));
  p.base = static_cast<uint32_t>(first);
  p.first = static_cast<uint32_t>(out);
  const uint32_t local = 64;
  dev.dispatch(dev.kernel(KernelId::point_codes), dev.groups_for(m, local), local, {&xb, &keys, &values}, p);
  dev.barrier();
}

}  // namespace

void point_codes(Device& dev, std::span<const int32_t> xyz, const PointCube& cube, std::vector<uint64_t>& codes,
                 std::vector<uint32_t>& index) {
  const uint64_t n = xyz.size() / 3;
  if (n > std::numeric_limits<uint32_t>::max())
    throw Error("points: " + std::to_string(n) + " points in one in-core sort run, over the 2^32 its indices hold");
  reserve_huge(codes, n);
  reserve_huge(index, n);
  codes.resize(n);
  index.resize(n);
  if (n == 0) return;
  // Per point: 12 bytes of coordinates, 8 of code and 4 of index. Chunks of 8M points keep the device buffers
  // small enough to stay warm (fresh device memory costs a page fault per page on first touch).
  const uint64_t chunk =
      std::min<uint64_t>({n, uint64_t{1} << 23, detail::device_chunk(dev, "point_codes", 24, 12)});
  Buffer xb = dev.alloc(chunk * 12, "point coordinates");
  Buffer kb = dev.alloc(chunk * 8, "point codes");
  Buffer ib = dev.alloc(chunk * 4, "point indices");
  for (uint64_t first = 0; first < n; first += chunk) {
    const uint64_t m = std::min(chunk, n - first);
    dispatch_codes(dev, xb, xyz, cube, first, m, kb, ib, 0);
    dev.download(kb, codes.data() + first, m * 8);
    dev.download(ib, index.data() + first, m * 4);
  }
}

bool sorted_codes_in_place(Device& dev, std::span<const int32_t> xyz, const PointCube& cube, SortedCodes& out,
                           const SortedCodesPrefix& on_prefix, uint32_t ranges) {
  const uint64_t n = xyz.size() / 3;
  if (n == 0 || n > std::numeric_limits<uint32_t>::max() || uint64_t{n} * 8 > dev.info().max_binding_bytes) return false;
  auto t0 = std::chrono::steady_clock::now();
  bool handed = false;  // the caller has had a prefix: from then on an error is its own, not a sort that did not fit
  try {
    Buffer keys = dev.alloc(n * 8, "point codes");
    Buffer values = dev.alloc(n * 4, "point indices");
    if (!dev.host_view(keys) || !dev.host_view(values)) return false;
    const uint64_t chunk = std::min<uint64_t>({n, uint64_t{1} << 23, detail::device_chunk(dev, "point_codes", 12, 12)});
    {
      Buffer xb = dev.alloc(chunk * 12, "point coordinates");
      for (uint64_t first = 0; first < n; first += chunk)
        dispatch_codes(dev, xb, xyz, cube, first, std::min(chunk, n - first), keys, values, first);
      dev.finish();  // the coordinates' buffer goes back before the sort takes its scratch
    }
    out.codes_seconds = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    SortedPrefix hand;  // empty without on_prefix: then the sort hands nothing over
    if (on_prefix)
      hand = [&](const Buffer& k, const Buffer* v, uint64_t end) {
        handed = true;
        on_prefix({static_cast<const uint64_t*>(dev.host_view(k)), n},
                  {static_cast<const uint32_t*>(dev.host_view(*v)), n}, end);
      };
    out.sort = radix_sort(dev, keys, &values, n, KeyBits::k64, SortStrategy::Auto, hand, ranges);
    dev.finish();
    out.sort_seconds = seconds_since(t0);
    out.codes = {static_cast<const uint64_t*>(dev.host_view(keys)), n};
    out.index = {static_cast<const uint32_t*>(dev.host_view(values)), n};
    out.keys = std::move(keys);
    out.values = std::move(values);
    return true;
  } catch (const DeviceMemoryError&) {
    if (handed) throw;
    dev.finish();
    return false;
  }
}

void set_grid_and_counts(PointHierarchy& h, const PointCloudInfo& info, const PointCube& cube, uint32_t grid_bits,
                         uint64_t points) {
  h.source = info;
  for (int a = 0; a < 3; ++a) h.cube_min[a] = cube.min[a];
  h.shift = cube.shift;
  h.grid_bits = grid_bits;
  h.depth = static_cast<uint32_t>(h.nodes_per_level.size() - 1);
  h.points_in = h.points_kept = points;
  h.points_dropped = 0;
}

}  // namespace mv::points
