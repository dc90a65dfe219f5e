// What the device splat renderer and its CPU reference share: the camera in the splat kernels' fixed point, the
// LOD cut, the cut's points as cells and colours, and the image made of the per-pixel winners. No device types.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "common/splat.h"
#include "megavox/point_render.h"

namespace mv::points {

struct SplatFrame {
  MvSplatParams params{};        // n and base are set per dispatch
  std::vector<uint32_t> nodes;   // the cut: node indices drawn
  std::vector<uint32_t> cells;   // 3 cell coordinates per drawn point
  std::vector<uint8_t> colours;  // 3 bytes per drawn point
};

// What the camera frames, on the input's grid (a fixed box keeps the camera still over a sequence of frames).
struct FrameBox {
  int64_t lo[3], hi[3];
};
// The box of a hierarchy's points.
FrameBox points_box(const PointColumns& points);

// The whole-frame setup: camera from options framing `box` (default: the points'), the cut by screen-space size
// from each of `roots` (a finished hierarchy: {0}; a partial one: its forest's roots), the cut's points.
SplatFrame splat_frame(const PointHierarchy& h, const PointRenderOptions& options,
                       const std::vector<uint32_t>& roots = {0}, const FrameBox* box = nullptr);

// The cut's rule alone, for a front kept across frames (omicron_front.h): from the camera `options` and `box`
// give over `grid` (a hierarchy's grid: source, cube, shift, grid bits; no nodes needed), whether a node's points'
// spacing projects to at most options.lod_pixels (0: never), so that it is drawn instead of its children.
class LodRule {
 public:
  LodRule(const PointHierarchy& grid, const PointRenderOptions& options, const FrameBox& box);
  ~LodRule();
  LodRule(LodRule&&) noexcept;
  bool fine_enough(uint32_t level, uint64_t prefix) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The picture: each covered pixel takes its winning point's colour, darkened by eye-dome lighting from the depth
// keys; uncovered pixels the background.
Image resolve_frame(const SplatFrame& frame, const std::vector<uint32_t>& depth, const std::vector<uint32_t>& index,
                    uint64_t* covered = nullptr);

}  // namespace mv::points
