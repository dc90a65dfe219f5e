#include "point_runs.h"

#include <algorithm>
#include <cstring>
#include <queue>

#include "megavox/error.h"
#include "megavox/primitives.h"

namespace mv::points {

RecordLayout record_layout(const PointCloudInfo& info) {
  RecordLayout r;
  r.attributes = info.attributes;
  r.extra_bytes = info.attributes & kPointExtra ? info.extra_bytes : 0;
  r.bytes = 8 + 12 + (info.attributes & kPointRgb ? 6 : 0) + (info.attributes & kPointNormal ? 12 : 0) +
            (info.attributes & kPointIntensity ? 2 : 0) + r.extra_bytes;
  return r;
}

void pack(const RecordLayout& r, const PointColumns& c, uint64_t i, uint64_t code, uint8_t* out) {
  std::memcpy(out, &code, 8);
  out += 8;
  std::memcpy(out, &c.xyz[3 * i], 12);
  out += 12;
  if (r.attributes & kPointRgb) std::memcpy(out, &c.rgb[3 * i], 6), out += 6;
  if (r.attributes & kPointNormal) std::memcpy(out, &c.normal[3 * i], 12), out += 12;
  if (r.attributes & kPointIntensity) std::memcpy(out, &c.intensity[i], 2), out += 2;
  if (r.extra_bytes) std::memcpy(out, &c.extra[i * r.extra_bytes], r.extra_bytes);
}

void unpack_at(const RecordLayout& r, const uint8_t* rec, PointColumns& out, uint64_t i) {
  rec += 8;
  std::memcpy(&out.xyz[3 * i], rec, 12);
  rec += 12;
  if (r.attributes & kPointRgb) std::memcpy(&out.rgb[3 * i], rec, 6), rec += 6;
  if (r.attributes & kPointNormal) std::memcpy(&out.normal[3 * i], rec, 12), rec += 12;
  if (r.attributes & kPointIntensity) std::memcpy(&out.intensity[i], rec, 2), rec += 2;
  if (r.extra_bytes) std::memcpy(&out.extra[i * r.extra_bytes], rec, r.extra_bytes);
}

PointColumns columns_for(const RecordLayout& r, uint64_t n) {
  PointColumns c;
  c.xyz.resize(3 * n);
  if (r.attributes & kPointRgb) c.rgb.resize(3 * n);
  if (r.attributes & kPointNormal) c.normal.resize(3 * n);
  if (r.attributes & kPointIntensity) c.intensity.resize(n);
  c.extra.resize(n * r.extra_bytes);
  return c;
}

void unpack(const RecordLayout& r, const uint8_t* rec, PointColumns& out) {
  rec += 8;
  const int32_t* xyz = reinterpret_cast<const int32_t*>(rec);
  int32_t p[3];
  std::memcpy(p, xyz, 12);
  out.xyz.insert(out.xyz.end(), p, p + 3);
  rec += 12;
  if (r.attributes & kPointRgb) {
    uint16_t v[3];
    std::memcpy(v, rec, 6);
    out.rgb.insert(out.rgb.end(), v, v + 3);
    rec += 6;
  }
  if (r.attributes & kPointNormal) {
    float v[3];
    std::memcpy(v, rec, 12);
    out.normal.insert(out.normal.end(), v, v + 3);
    rec += 12;
  }
  if (r.attributes & kPointIntensity) {
    uint16_t v;
    std::memcpy(&v, rec, 2);
    out.intensity.push_back(v);
    rec += 2;
  }
  if (r.extra_bytes) out.extra.insert(out.extra.end(), rec, rec + r.extra_bytes);
}

RunSorter::RunSorter(Device& dev, const PointCloudInfo& info, const PointCube& cube)
    : dev_(dev), layout_(record_layout(info)), cube_(cube) {}

RunSorter::~RunSorter() = default;

void RunSorter::add_run(const PointColumns& run) {
  const uint64_t n = run.size();
  if (n == 0) return;
  std::vector<uint64_t> codes;
  std::vector<uint32_t> index;
  point_codes(dev_, run.xyz, cube_, codes, index);
  radix_sort(dev_, codes, &index);
  Run r;
  r.file = std::make_unique<io::TempFile>("sorting points out of core");
  r.records = n;
  // Written in blocks: a run's records in sorted order.
  const uint64_t block = std::max<uint64_t>(1, (uint64_t{4} << 20) / layout_.bytes);
  std::vector<uint8_t> buf(block * layout_.bytes);
  for (uint64_t first = 0; first < n; first += block) {
    const uint64_t m = std::min(block, n - first);
    for (uint64_t k = 0; k < m; ++k) pack(layout_, run, index[first + k], codes[first + k], &buf[k * layout_.bytes]);
    r.file->write_at(buf.data(), m * layout_.bytes, first * layout_.bytes);
  }
  points_ += n;
  runs_.push_back(std::move(r));
}

void RunSorter::merge(size_t batch_records, const std::function<void(const uint8_t*, size_t)>& sink) {
  const uint32_t rb = layout_.bytes;
  // Each run is read through its own buffer of `per_run` records.
  const uint64_t per_run = std::max<uint64_t>(16, (uint64_t{1} << 20) / rb);
  struct Cursor {
    std::vector<uint8_t> buf;
    uint64_t next = 0, loaded = 0, at = 0;  // next record to load from the file; records in buf; position in buf
  };
  std::vector<Cursor> cur(runs_.size());
  auto refill = [&](size_t k) {
    Cursor& c = cur[k];
    const uint64_t m = std::min(per_run, runs_[k].records - c.next);
    c.buf.resize(m * rb);
    if (m) runs_[k].file->read_at(c.buf.data(), m * rb, c.next * rb);
    c.next += m;
    c.loaded = m;
    c.at = 0;
    return m > 0;
  };
  // The heap orders by (code, run): of equal codes the earlier run, i.e. the earlier input, comes first.
  using Key = std::pair<uint64_t, size_t>;
  std::priority_queue<Key, std::vector<Key>, std::greater<Key>> heap;
  for (size_t k = 0; k < runs_.size(); ++k)
    if (refill(k)) heap.push({record_code(cur[k].buf.data()), k});
  std::vector<uint8_t> out(std::max<size_t>(1, batch_records) * rb);
  size_t count = 0;
  while (!heap.empty()) {
    const size_t k = heap.top().second;
    heap.pop();
    Cursor& c = cur[k];
    std::memcpy(&out[count * rb], &c.buf[c.at * rb], rb);
    if (++count * rb == out.size()) {
      sink(out.data(), count);
      count = 0;
    }
    if (++c.at == c.loaded && !refill(k)) continue;
    heap.push({record_code(&c.buf[c.at * rb]), k});
  }
  if (count) sink(out.data(), count);
}

}  // namespace mv::points
