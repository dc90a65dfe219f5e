#include "io/memory_points.h"

#include <algorithm>
#include <cmath>

#include "io/ply_points.h"
#include "megavox/error.h"

namespace mv::io {

namespace {

class MemoryPoints final : public PointSource {
 public:
  MemoryPoints(const PointArrays& a, PointCloudInfo info, double scale)
      : a_(a), info_(std::move(info)), scale_(scale), inv_(1 / scale), exact_inverse_(std::isfinite(inv_) && inv_ * scale == 1) {}
  const PointCloudInfo& info() const override { return info_; }
  uint64_t records_read() const override { return next_; }

  bool next(PointColumns& out, size_t max_points) override {
    const uint64_t n = std::min<uint64_t>(max_points, info_.points - next_);
    if (n == 0) return false;
    const uint64_t base = out.size(), e = a_.extra_bytes;
    out.xyz.resize(3 * (base + n));
    for (uint64_t i = 0; i < 3 * n; ++i) {
      const double c = a_.xyz32.empty() ? a_.xyz64[3 * next_ + i] : double(a_.xyz32[3 * next_ + i]);
      // the scale is a power of two, so multiplying by its inverse divides exactly where the inverse exists
      const double q = exact_inverse_ ? c * inv_ : c / scale_;
      out.xyz[3 * base + i] = static_cast<int32_t>(std::llround(q));  // halves away from zero, as PLY
    }
    auto append = [&](auto& column, auto span, uint64_t per) {
      if (span.empty()) return;
      column.insert(column.end(), span.begin() + per * next_, span.begin() + per * (next_ + n));
    };
    append(out.rgb, a_.rgb, 3);
    append(out.intensity, a_.intensity, 1);
    append(out.extra, a_.extra, e);
    next_ += n;
    return true;
  }

 private:
  PointArrays a_;
  PointCloudInfo info_;
  double scale_, inv_;
  bool exact_inverse_;
  uint64_t next_ = 0;
};

}  // namespace

std::unique_ptr<PointSource> memory_points(const PointArrays& a, const std::string& label) {
  const bool single = !a.xyz32.empty() || a.xyz64.empty();
  if (!a.xyz32.empty() && !a.xyz64.empty()) throw Error(label + ": positions given both as float and as double");
  const size_t values = single ? a.xyz32.size() : a.xyz64.size();
  if (values % 3) throw Error(label + ": the position array holds " + std::to_string(values) + " values, not 3 per point");
  const uint64_t n = values / 3;
  auto check = [&](size_t size, uint64_t per, const char* what) {
    if (size != 0 && size != n * per)
      throw Error(label + ": the " + std::string(what) + " array holds " + std::to_string(size) + " values for " +
                  std::to_string(n) + " points (" + std::to_string(per) + " per point)");
  };
  check(a.rgb.size(), 3, "colour");
  check(a.intensity.size(), 1, "intensity");
  if (!a.extra.empty() && a.extra_bytes == 0) throw Error(label + ": extra bytes given with 0 bytes per point");
  check(a.extra.size(), a.extra_bytes, "extra byte");

  double max_abs = 0;
  for (size_t i = 0; i < values; ++i) {
    const double c = single ? double(a.xyz32[i]) : a.xyz64[i];
    if (!std::isfinite(c))
      throw Error(label + ": point " + std::to_string(i / 3) + ": coordinate " + std::string(1, "xyz"[i % 3]) +
                  " is not finite");
    max_abs = std::max(max_abs, std::fabs(c));
  }
  PointCloudInfo info;
  info.format = single ? "float32 arrays" : "float64 arrays";
  info.points = n;
  info.attributes = (a.rgb.empty() ? 0u : uint32_t{kPointRgb}) | (a.intensity.empty() ? 0u : uint32_t{kPointIntensity}) |
                    (a.extra.empty() ? 0u : uint32_t{kPointExtra});
  info.extra_bytes = a.extra.empty() ? 0 : a.extra_bytes;
  const double scale = ply_grid_scale(single ? PlyGrid::float32 : PlyGrid::float64, max_abs);
  for (double& s : info.scale) s = scale;
  info.z_up = false;  // as a PLY: +Y up
  PointArrays kept = a;
  if (a.extra.empty()) kept.extra_bytes = 0;
  return std::make_unique<MemoryPoints>(kept, std::move(info), scale);
}

}  // namespace mv::io
