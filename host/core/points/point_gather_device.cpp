// The node-order gather of point columns on the device (point_gather.h).
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstring>

#include "huge_pages.h"
#include "megavox/error.h"
#include "megavox/primitives.h"
#include "point_gather.h"

namespace mv::points {

namespace {

// Output records per chunk: a multiple of 4, so that every chunk but the last ends on a whole word.
constexpr uint64_t kChunkRecords = uint64_t{1} << 22;

// order[i] = the input position of node-order point i.
std::vector<uint32_t> composed_order(std::span<const uint32_t> index, std::span<const NodePoints> sources,
                                     std::span<const uint64_t> reps) {
  std::vector<uint64_t> offset(sources.size() + 1, 0);
  for (size_t k = 0; k < sources.size(); ++k) offset[k + 1] = offset[k] + sources[k].count;
  std::vector<uint32_t> order;
  reserve_huge(order, offset.back());
  order.resize(offset.back());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, sources.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k < r.end(); ++k) {
      const NodePoints& s = sources[k];
      uint32_t* out = order.data() + offset[k];
      if (s.reps)
        for (uint32_t i = 0; i < s.count; ++i) out[i] = index[reps[s.first + i]];
      else
        std::memcpy(out, index.data() + s.first, uint64_t{s.count} * 4);
    }
  });
  return order;
}

// One column: n source records of record_bytes bytes, through the order in chunks of `chunk` records, into out
// (order.size() records). A source within one binding is uploaded once, and each chunk of the order goes up, is
// gathered and comes back through the same two small buffers. A larger source goes in slices, each uploaded once:
// then every chunk's order and output stay on the device until the last slice has passed.
void device_gather(Device& dev, const uint8_t* src, uint64_t n, uint32_t record_bytes, std::span<const uint32_t> order,
                   uint64_t chunk, uint64_t slice_records, uint8_t* out) {
  const uint64_t binding = std::max<uint64_t>(dev.info().max_binding_bytes, 4096);
  uint64_t slice = std::max<uint64_t>(1, std::min<uint64_t>({n, (binding - 4) / record_bytes, UINT32_MAX}));
  if (slice_records) slice = std::min(slice, slice_records);
  const uint64_t m = order.size();
  auto words = [&](uint64_t records) { return std::max<uint64_t>((records * record_bytes + 3) / 4 * 4, 4); };
  if (slice >= n) {
    Buffer sb = dev.alloc(words(n), "point column");
    dev.upload(sb, src, n * record_bytes);
    Buffer ib = dev.alloc(std::min(chunk, m) * 4, "node order");
    Buffer db = dev.alloc(words(std::min(chunk, m)), "gathered points");
    for (uint64_t at = 0; at < m; at += chunk) {
      const uint64_t c = std::min(chunk, m - at);
      dev.upload(ib, order.data() + at, c * 4);
      dev.barrier();
      gather_records(dev, sb, ib, db, c, record_bytes);
      dev.download(db, out + at * record_bytes, c * record_bytes);
    }
    return;
  }
  std::vector<Buffer> ib, db;
  for (uint64_t at = 0; at < m; at += chunk) {
    const uint64_t c = std::min(chunk, m - at);
    ib.push_back(dev.alloc(c * 4, "node order"));
    dev.upload(ib.back(), order.data() + at, c * 4);
    db.push_back(dev.alloc(words(c), "gathered points"));
  }
  for (uint64_t lo = 0; lo < n; lo += slice) {
    const uint64_t count = std::min(slice, n - lo);
    Buffer sb = dev.alloc(words(count), "point column slice");
    dev.upload(sb, src + lo * record_bytes, count * record_bytes);
    dev.barrier();
    for (size_t k = 0; k < ib.size(); ++k)
      gather_records(dev, sb, ib[k], db[k], std::min(chunk, m - k * chunk), record_bytes,
                     {static_cast<uint32_t>(lo), static_cast<uint32_t>(count), lo > 0});
  }
  for (size_t k = 0; k < db.size(); ++k)
    dev.download(db[k], out + k * chunk * record_bytes, std::min(chunk, m - k * chunk) * record_bytes);
}

template <class T>
void gather_column(Device& dev, std::vector<T>&& src, uint64_t n, uint32_t per_point, std::span<const uint32_t> order,
                   uint64_t chunk, uint64_t slice, std::vector<T>& out) {
  if (src.empty()) return;
  const uint32_t record_bytes = static_cast<uint32_t>(per_point * sizeof(T));
  reserve_huge(out, order.size() * per_point);
  out.resize(order.size() * per_point);
  const auto* from = reinterpret_cast<const uint8_t*>(src.data());
  auto* to = reinterpret_cast<uint8_t*>(out.data());
  try {
    device_gather(dev, from, n, record_bytes, order, chunk, slice, to);
  } catch (const DeviceMemoryError&) {
    dev.finish();  // the device cannot hold this column's buffers: the host gathers it
    gather_record_bytes(from, record_bytes, order, to);
  }
  src = std::vector<T>();
}

}  // namespace

PointColumns gather_node_points(Device& dev, PointColumns&& points, std::span<const uint32_t> index,
                                std::span<const NodePoints> sources, std::span<const uint64_t> reps,
                                uint32_t extra_bytes, uint64_t chunk_records, uint64_t slice_records) {
  const uint64_t n = points.size();
  const std::vector<uint32_t> order = composed_order(index, sources, reps);
  const uint64_t binding = std::max<uint64_t>(dev.info().max_binding_bytes, 4096);
  const uint64_t chunk =
      std::max<uint64_t>(4, std::min<uint64_t>(chunk_records ? chunk_records : kChunkRecords, binding / 16) / 4 * 4);
  PointColumns out;
  gather_column(dev, std::move(points.xyz), n, 3, order, chunk, slice_records, out.xyz);
  gather_column(dev, std::move(points.rgb), n, 3, order, chunk, slice_records, out.rgb);
  gather_column(dev, std::move(points.normal), n, 3, order, chunk, slice_records, out.normal);
  gather_column(dev, std::move(points.intensity), n, 1, order, chunk, slice_records, out.intensity);
  if (extra_bytes) gather_column(dev, std::move(points.extra), n, extra_bytes, order, chunk, slice_records, out.extra);
  return out;
}

}  // namespace mv::points
