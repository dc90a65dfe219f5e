// The C API: a .mvx point hierarchy read back (its nodes and its points' columns), for callers that draw or
// analyse it themselves.
#include <algorithm>
#include <cstddef>
#include <cstring>
#include <memory>

#include "handles.h"
#include "megavox/mvx.h"

MvPointsTy::~MvPointsTy() {
  if (device) mvReleaseDevice(device);
}

namespace mv::capi {

namespace {

static_assert(sizeof(MvPointNode) == sizeof(PointNode) && sizeof(MvPointNode) == 40,
              "MvPointNode is the 40-byte node .mvx stores");
static_assert(offsetof(MvPointNode, subtreePoints) == offsetof(PointNode, subtree_points) &&
              offsetof(MvPointNode, pointCount) == offsetof(PointNode, point_count) &&
              offsetof(MvPointNode, firstChild) == offsetof(PointNode, first_child) &&
              offsetof(MvPointNode, childMask) == offsetof(PointNode, child_mask) &&
              offsetof(MvPointNode, level) == offsetof(PointNode, level));
static_assert(MV_POINT_RGB == kPointRgb && MV_POINT_NORMAL == kPointNormal && MV_POINT_INTENSITY == kPointIntensity &&
              MV_POINT_EXTRA == kPointExtra);

// [first, first + count) within [0, size), or an error naming `what`.
void require_range(uint64_t first, uint64_t count, uint64_t size, const char* what) {
  if (first > size || count > size - first)
    throw ApiError(MV_ERROR_INVALID_ARGUMENT, std::string(what) + " [" + std::to_string(first) + ", " +
                                                  std::to_string(first) + " + " + std::to_string(count) +
                                                  ") reaches past the " + std::to_string(size) + " there are");
}

}  // namespace

}  // namespace mv::capi

using namespace mv::capi;

extern "C" {

MvPoints mvOpenPoints(MvDevice device, const char* path) {
  MvPoints made = nullptr;
  guard(device, [&] {
    require(device, "mvOpenPoints: no device");
    require(path && *path, "mvOpenPoints: no path");
    auto p = std::make_unique<MvPointsTy>();
    p->hierarchy = mv::read_mvx_points(path);
    mvRetainDevice(device);
    p->device = device;
    made = p.release();
  });
  return made;
}

void mvRetainPoints(MvPoints points) { retain(points); }

void mvReleasePoints(MvPoints points) { release(points); }

MvError mvGetPointsInfo(MvPoints points, MvPointsInfo* info) {
  const MvDevice device = points ? points->device : nullptr;
  return guard(device, [&] {
    require(points, "mvGetPointsInfo: no point hierarchy");
    require(info, "mvGetPointsInfo: info is NULL");
    const mv::PointHierarchy& h = points->hierarchy;
    *info = MvPointsInfo{};
    info->nodes = h.nodes.size();
    info->points = h.points.size();
    info->pointsIn = h.points_in;
    info->pointsKept = h.points_kept;
    info->pointsDropped = h.points_dropped;
    info->depth = h.depth;
    info->attributes = h.source.attributes;
    info->extraBytes = h.source.extra_bytes;
    for (int a = 0; a < 3; ++a) {
      info->scale[a] = h.source.scale[a];
      info->offset[a] = h.source.offset[a];
    }
    copy_text(info->format, h.source.format);
  });
}

size_t mvGetPointsCrs(MvPoints points, char* text, size_t capacity) {
  size_t length = 0;
  guard(points ? points->device : nullptr, [&] {
    require(points, "mvGetPointsCrs: no point hierarchy");
    require(text || capacity == 0, "mvGetPointsCrs: text is NULL");
    const std::string& crs = points->hierarchy.source.crs;
    if (capacity) {
      const size_t n = std::min(crs.size(), capacity - 1);
      crs.copy(text, n);
      text[n] = '\0';
    }
    length = crs.size();
  });
  return length;
}

size_t mvGetPointFields(MvPoints points, MvPointField* fields, size_t capacity) {
  size_t n = 0;
  guard(points ? points->device : nullptr, [&] {
    require(points, "mvGetPointFields: no point hierarchy");
    require(fields || capacity == 0, "mvGetPointFields: fields is NULL");
    const std::vector<mv::PointField>& all = points->hierarchy.source.fields;
    for (size_t i = 0; i < std::min(capacity, all.size()); ++i) {
      MvPointField& f = fields[i];
      f = MvPointField{};
      const size_t len = std::min(all[i].name.size(), sizeof f.name - 1);
      all[i].name.copy(f.name, len);
      f.type = static_cast<uint32_t>(all[i].type);
      f.offset = all[i].offset;
      f.count = all[i].count;
      f.scale = all[i].scale;
      f.add = all[i].add;
    }
    n = all.size();
  });
  return n;
}

MvError mvGetPointNodes(MvPoints points, uint64_t first, uint64_t count, MvPointNode* nodes) {
  const MvDevice device = points ? points->device : nullptr;
  return guard(device, [&] {
    require(points, "mvGetPointNodes: no point hierarchy");
    require(nodes || count == 0, "mvGetPointNodes: nodes is NULL");
    const auto& all = points->hierarchy.nodes;
    require_range(first, count, all.size(), "mvGetPointNodes: nodes");
    if (count) std::memcpy(nodes, all.data() + first, count * sizeof(MvPointNode));
  });
}

MvError mvGetPointData(MvPoints points, uint64_t first, uint64_t count, double* xyz, uint16_t* rgb, uint16_t* intensity,
                       uint8_t* extra, float* normal) {
  const MvDevice device = points ? points->device : nullptr;
  return guard(device, [&] {
    require(points, "mvGetPointData: no point hierarchy");
    const mv::PointHierarchy& h = points->hierarchy;
    const mv::PointColumns& c = h.points;
    require_range(first, count, c.size(), "mvGetPointData: points");
    const uint32_t a = h.source.attributes;
    require(!rgb || (a & mv::kPointRgb), "mvGetPointData: the hierarchy carries no colours (rgb must be NULL)");
    require(!intensity || (a & mv::kPointIntensity),
            "mvGetPointData: the hierarchy carries no intensities (intensity must be NULL)");
    require(!extra || (a & mv::kPointExtra), "mvGetPointData: the hierarchy carries no extra bytes (extra must be NULL)");
    require(!normal || (a & mv::kPointNormal), "mvGetPointData: the hierarchy carries no normals (normal must be NULL)");
    if (xyz)
      for (uint64_t i = 0; i < count; ++i)
        for (int k = 0; k < 3; ++k)
          xyz[3 * i + k] = h.source.offset[k] + h.source.scale[k] * double(c.xyz[3 * (first + i) + k]);
    if (rgb && count) std::memcpy(rgb, c.rgb.data() + 3 * first, count * 6);
    if (intensity && count) std::memcpy(intensity, c.intensity.data() + first, count * 2);
    const uint64_t e = h.source.extra_bytes;
    if (extra && count) std::memcpy(extra, c.extra.data() + e * first, count * e);
    if (normal && count) std::memcpy(normal, c.normal.data() + 3 * first, count * 12);
  });
}

}  // extern "C"
