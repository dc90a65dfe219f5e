#include "tiles3d_place.h"

#include <algorithm>
#include <cstdint>
#include <limits>

#include "crs_frame.h"
#include "megavox/error.h"

namespace mv::io {

std::string tiles3d_usable_crs(const std::string& declared) {
  const std::string geotiff = "GeoTIFF keys";
  if (declared.compare(0, geotiff.size(), geotiff) != 0) return declared;
  const std::string code = " (EPSG:";
  if (declared.compare(geotiff.size(), code.size(), code) != 0 || declared.back() != ')') return {};
  return declared.substr(geotiff.size() + 2, declared.size() - geotiff.size() - 3);  // "EPSG:N"
}

TilePlacement tiles3d_place(const PointHierarchy& h, const std::string& crs) {
  // Every stored point is a leaf's or a copy of one: their bounds are the cloud's.
  const auto& xyz = h.points.xyz;
  if (xyz.size() < 3) throw Error("the point hierarchy holds no points to place");
  int64_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = hi[a] = xyz[a];
  for (size_t i = 3; i < xyz.size(); i += 3)
    for (int a = 0; a < 3; ++a) lo[a] = std::min<int64_t>(lo[a], xyz[i + a]), hi[a] = std::max<int64_t>(hi[a], xyz[i + a]);
  return tiles3d_place(h.source, lo, hi, crs);
}

TilePlacement tiles3d_place(const PointCloudInfo& source, const int64_t lo[3], const int64_t hi[3], const std::string& crs) {
  TilePlacement p;
  p.declared = source.crs;
  for (int a = 0; a < 3; ++a) {
    const double s = source.scale[a], o = source.offset[a];
    const double x = o + s * lo[a], y = o + s * hi[a];  // a negative scale swaps them
    p.lo[a] = std::min(x, y), p.hi[a] = std::max(x, y);
    p.origin[a] = p.lo[a] + (p.hi[a] - p.lo[a]) / 2;
  }

  std::string use = crs;
  if (use.empty()) {
    use = tiles3d_usable_crs(p.declared);
    if (use.empty() && !p.declared.empty()) p.note = "the declared CRS (" + p.declared + ") names no EPSG code";
  }
  if (!use.empty()) {
    try {
      const CrsFrame f = crs_frame(use, p.origin);
      double half[3];
      for (int a = 0; a < 3; ++a) half[a] = (p.hi[a] - p.lo[a]) / 2;
      p.error_metres = crs_frame_error_metres(use, p.origin, half, &p.vertical_error_metres);
      std::copy(f.transform, f.transform + 16, p.transform);
      std::copy(f.units_to_metres, f.units_to_metres + 3, p.units_to_metres);
      p.crs = use;
      p.crs_name = f.crs_name;
      return p;
    } catch (const Error& e) {
      if (!crs.empty()) throw;  // the user's own choice must work
      p.note = e.what();
    }
  }
  // Local: the input's own units, put back where they were by a translation.
  p.transform[0] = p.transform[5] = p.transform[10] = p.transform[15] = 1;
  for (int a = 0; a < 3; ++a) p.transform[12 + a] = p.origin[a];
  return p;
}

}  // namespace mv::io
