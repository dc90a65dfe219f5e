// megavox — pictures of a point hierarchy: an LOD cut chosen by screen-space size, drawn as depth-tested square
// splats by the splat kernels (kernels/common/splat.h), coloured and shaded (eye-dome lighting) on the host.
#pragma once
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "megavox/points.h"
#include "megavox/render.h"

namespace mv {

class Device;  // megavox/device.h

// The camera: a preset view framing the cloud, or an eye (and a target, default the cloud's centre) in the input's
// own units. Presets look along the axes, with the axis nearest the up direction up.
struct PointRenderOptions {
  uint32_t width = 1920, height = 1080;
  std::string view = "iso";  // front, back, left, right, top, iso
  std::optional<std::array<double, 3>> eye, target;
  std::optional<std::array<double, 3>> up;  // unset: the file's (+Z for LAS input, +Y for PLY)
  double fov = 40;           // vertical, degrees
  double lod_pixels = 1.0;   // a node is drawn when its points' spacing projects to at most this many pixels
  uint32_t point_size = 3;   // splat side in pixels (odd; even sizes round up)
};

struct PointRenderResult {
  Image image;
  uint64_t nodes_drawn = 0, points_drawn = 0;
  uint64_t pixels_covered = 0;
  std::vector<uint32_t> depth, winner;  // per pixel: the splat kernels' depth key and winning point (cut order)
};

PointRenderResult render_points(Device& dev, const PointHierarchy& h, const PointRenderOptions& options);

// `points render --during-build`: builds the cloud file `input` and renders `frames` pictures while it grows,
// DIR/frame_0000.png ..., the last of the finished hierarchy's cut, from one camera framing the whole cloud. The
// frames before it draw OMiCroN's rendering front (host/core/points/omicron_front.h), kept across the build, with
// render.lod_pixels as its rule: 0 draws every formed point. DIR is written through a temporary folder.
struct BuildFrame {
  uint32_t frame = 0;
  uint64_t nodes = 0;        // made so far, every level (never shrinks)
  uint64_t front_nodes = 0;  // drawn: the front's entries (the last frame: the finished hierarchy's cut)
  uint64_t points_drawn = 0;
  std::string path;
};
struct PointBuildOptions;  // megavox/point_build.h
void render_during_build(Device& dev, const std::string& input, const std::string& dir, uint32_t frames,
                         const PointBuildOptions& build, const PointRenderOptions& render,
                         const std::function<void(const BuildFrame&)>& on_frame);

}  // namespace mv
