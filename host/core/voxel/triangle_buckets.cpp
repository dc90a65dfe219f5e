#include "voxel/triangle_buckets.h"

#include <algorithm>
#include <cmath>

namespace mv {

TriangleBuckets::TriangleBuckets(uint32_t per_axis, uint32_t cube, uint64_t budget, uint32_t record_floats)
    : per_axis_(per_axis), cube_(cube), record_(std::max<uint32_t>(record_floats, 9)), budget_(budget) {
  const size_t n = size_t{per_axis} * per_axis * per_axis;
  mem_.resize(n);
  chunks_.resize(n);
  estimate_.assign(n, 0.0);
}

void TriangleBuckets::add(const std::vector<float>& tris) {
  for (size_t t = 0; t + record_ <= tris.size(); t += record_) {
    uint32_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      const double mn = std::min({double(tris[t + a]), double(tris[t + 3 + a]), double(tris[t + 6 + a])});
      const double mx = std::max({double(tris[t + a]), double(tris[t + 3 + a]), double(tris[t + 6 + a])});
      lo[a] = std::min<uint32_t>(per_axis_ - 1, static_cast<uint32_t>(std::max(0.0, std::floor(mn)) / cube_));
      hi[a] = std::min<uint32_t>(per_axis_ - 1, static_cast<uint32_t>(std::max(0.0, std::floor(mx)) / cube_));
    }
    double e[2][3];  // the edges from the first corner, and the normal's largest component: twice the area seen
    for (int k = 0; k < 2; ++k)
      for (int a = 0; a < 3; ++a) e[k][a] = double(tris[t + 3 * (k + 1) + a]) - double(tris[t + a]);
    const double seen = std::max({std::fabs(e[0][1] * e[1][2] - e[0][2] * e[1][1]),
                                  std::fabs(e[0][2] * e[1][0] - e[0][0] * e[1][2]),
                                  std::fabs(e[0][0] * e[1][1] - e[0][1] * e[1][0])}) / 2;
    const double share = (seen + 1) / (double(hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1));
    for (uint32_t x = lo[0]; x <= hi[0]; ++x)
      for (uint32_t y = lo[1]; y <= hi[1]; ++y)
        for (uint32_t z = lo[2]; z <= hi[2]; ++z) {
          std::vector<float>& b = mem_[bucket(x, y, z)];
          b.insert(b.end(), tris.begin() + t, tris.begin() + t + record_);
          held_ += record_ * sizeof(float);
          estimate_[bucket(x, y, z)] += share;
        }
    if (held_ > budget_) spill();
  }
}

void TriangleBuckets::put(uint32_t x, uint32_t y, uint32_t z, const std::vector<float>& records) {
  std::vector<float>& b = mem_[bucket(x, y, z)];
  b.insert(b.end(), records.begin(), records.end());
  held_ += records.size() * sizeof(float);
  if (held_ > budget_) spill();
}

void TriangleBuckets::spill() {
  if (!spill_) spill_ = std::make_unique<io::TempFile>("spilling triangles (over the host memory budget)");
  for (size_t b = 0; b < mem_.size(); ++b) {
    std::vector<float>& v = mem_[b];
    if (v.empty()) continue;
    spill_->write_at(v.data(), v.size() * sizeof(float), file_bytes_);
    chunks_[b].push_back({file_bytes_, v.size()});
    file_bytes_ += v.size() * sizeof(float);
    std::vector<float>().swap(v);  // give the memory back
  }
  held_ = 0;
}

std::vector<float> TriangleBuckets::take(uint32_t x, uint32_t y, uint32_t z) {
  const size_t b = bucket(x, y, z);
  std::vector<float> out;
  uint64_t floats = mem_[b].size();
  for (const Chunk& c : chunks_[b]) floats += c.floats;
  out.reserve(floats);
  for (const Chunk& c : chunks_[b]) {
    const size_t at = out.size();
    out.resize(at + c.floats);
    spill_->read_at(out.data() + at, c.floats * sizeof(float), c.offset);
  }
  out.insert(out.end(), mem_[b].begin(), mem_[b].end());
  held_ -= mem_[b].size() * sizeof(float);
  std::vector<float>().swap(mem_[b]);
  std::vector<Chunk>().swap(chunks_[b]);
  return out;
}

}  // namespace mv
