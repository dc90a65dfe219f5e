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

// The order's chunks, uploaded once for every column.
struct OrderChunks {
  std::vector<Buffer> index;
  std::vector<uint64_t> first;  // first[c]: chunk c's first output record; first.back() = the total
};

OrderChunks upload_order(Device& dev, std::span<const uint32_t> order, uint64_t chunk) {
  OrderChunks oc;
  for (uint64_t at = 0; at < order.size(); at += chunk) {
    const uint64_t m = std::min(chunk, order.size() - at);
    oc.index.push_back(dev.alloc(m * 4, "node order"));
    dev.upload(oc.index.back(), order.data() + at, m * 4);
    oc.first.push_back(at);
  }
  oc.first.push_back(order.size());
  return oc;
}

// out record i = src record order[i] on the host, for a column the device cannot hold.
void host_gather(const uint8_t* src, uint32_t record_bytes, std::span<const uint32_t> order, uint8_t* out) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, order.size(), 1 << 14), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i < r.end(); ++i)
      std::memcpy(out + i * record_bytes, src + uint64_t{order[i]} * record_bytes, record_bytes);
  });
}

// One column: n source records of record_bytes bytes, through the order's chunks, into out (order.size() records).
// Source slices go outer (each uploaded once), output chunks inner; every chunk's buffer stays until the last
// slice has passed.
void device_gather(Device& dev, const uint8_t* src, uint64_t n, uint32_t record_bytes, const OrderChunks& oc,
                   uint8_t* out) {
  const uint64_t binding = std::max<uint64_t>(dev.info().max_binding_bytes, 4096);
  const uint64_t slice = std::max<uint64_t>(1, std::min<uint64_t>({n, (binding - 4) / record_bytes, UINT32_MAX}));
  std::vector<Buffer> dst;
  for (size_t c = 0; c + 1 < oc.first.size(); ++c)
    dst.push_back(dev.alloc(((oc.first[c + 1] - oc.first[c]) * record_bytes + 3) / 4 * 4, "gathered points"));
  for (uint64_t lo = 0; lo < n; lo += slice) {
    const uint64_t count = std::min(slice, n - lo);
    Buffer sb = dev.alloc((count * record_bytes + 3) / 4 * 4, "point column");
    dev.upload(sb, src + lo * record_bytes, count * record_bytes);
    dev.barrier();
    for (size_t c = 0; c < dst.size(); ++c)
      gather_records(dev, sb, oc.index[c], dst[c], oc.first[c + 1] - oc.first[c], record_bytes,
                     {static_cast<uint32_t>(lo), static_cast<uint32_t>(count), lo > 0});
  }
  for (size_t c = 0; c < dst.size(); ++c)
    dev.download(dst[c], out + oc.first[c] * record_bytes, (oc.first[c + 1] - oc.first[c]) * record_bytes);
}

template <class T>
void gather_column(Device& dev, const std::vector<T>& src, uint64_t n, uint32_t per_point, std::span<const uint32_t> order,
                   const OrderChunks* oc, std::vector<T>& out) {
  if (src.empty()) return;
  const uint32_t record_bytes = static_cast<uint32_t>(per_point * sizeof(T));
  reserve_huge(out, order.size() * per_point);
  out.resize(order.size() * per_point);
  const auto* from = reinterpret_cast<const uint8_t*>(src.data());
  auto* to = reinterpret_cast<uint8_t*>(out.data());
  if (oc) {
    try {
      device_gather(dev, from, n, record_bytes, *oc, to);
      return;
    } catch (const DeviceMemoryError&) {
      dev.finish();  // the device cannot hold this column's buffers: the host gathers it
    }
  }
  host_gather(from, record_bytes, order, to);
}

}  // namespace

PointColumns gather_node_points(Device& dev, const PointColumns& points, std::span<const uint32_t> index,
                                std::span<const NodePoints> sources, std::span<const uint64_t> reps,
                                uint32_t extra_bytes, uint64_t chunk_records) {
  const uint64_t n = points.size();
  const std::vector<uint32_t> order = composed_order(index, sources, reps);
  const uint64_t binding = std::max<uint64_t>(dev.info().max_binding_bytes, 4096);
  const uint64_t chunk =
      std::max<uint64_t>(4, std::min<uint64_t>(chunk_records ? chunk_records : kChunkRecords, binding / 16) / 4 * 4);
  OrderChunks oc;
  bool on_device = true;
  try {
    oc = upload_order(dev, order, chunk);
  } catch (const DeviceMemoryError&) {
    dev.finish();
    on_device = false;
  }
  const OrderChunks* use = on_device ? &oc : nullptr;
  PointColumns out;
  gather_column(dev, points.xyz, n, 3, order, use, out.xyz);
  gather_column(dev, points.rgb, n, 3, order, use, out.rgb);
  gather_column(dev, points.normal, n, 3, order, use, out.normal);
  gather_column(dev, points.intensity, n, 1, order, use, out.intensity);
  if (extra_bytes) gather_column(dev, points.extra, n, extra_bytes, order, use, out.extra);
  return out;
}

}  // namespace mv::points
