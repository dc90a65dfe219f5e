// megavox — pictures of an encoded voxel DAG: pinhole camera, primary / shadow / ambient-occlusion rays
// through the traversal kernel, shading on the host, PNG out.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "megavox/cache_stats.h"
#include "megavox/image.h"
#include "megavox/mvx.h"

namespace mv {

class Tracer;  // megavox/trace.h

enum class Shading {
  shaded,  // diffuse light with hard shadows and ambient occlusion
  normal,  // face normal as colour
  depth,   // distance along the view axis, near = bright
  level,   // false colour per level of detail the ray stopped at
  heat,    // traversal steps per pixel (log scale)
  colour,  // the voxel colours as stored, unlit (grey where the file has none)
};
Shading parse_shading(const std::string& name);  // throws mv::Error naming the choices
std::string shading_name(Shading s);

// A pinhole camera in the model's own units; fov is the vertical field of view in degrees.
struct Camera {
  double eye[3] = {0, 0, 1};
  double target[3] = {0, 0, 0};
  double up[3] = {0, 1, 0};
  double fov = 40;
};

// A camera framing `bounds` from one side: front (from +Z), back (-Z), left (-X), right (+X), top (+Y),
// iso (from +X+Y+Z); +Y is up (top: -Z is up). Throws mv::Error for other names.
Camera view_camera(const Bounds& bounds, const std::string& view, double fov = 40);

struct RenderOptions {
  uint32_t width = 1920, height = 1080;
  Shading shading = Shading::shaded;
  double lod_pixels = 1;     // stop at cells that project smaller than this many pixels; 0 = voxels only
  uint32_t ao_samples = 8;   // ambient-occlusion rays per hit (0 = no AO); at most 256
  double ao_radius = 0;      // in model units; 0 = 1/20 of the grid's side
  uint32_t max_steps = 60000;
  // Paged tracers (megavox/trace.h): passes per tile at most, each tracing every ray of the tile (the frame,
  // or a band of it when the frame's pages exceed the cache) and then loading the pages it missed; 0 = until a
  // pass misses none. The picture is the last passes': where they still met missing pages, it shows the finest
  // resident level.
  uint32_t cache_passes = 0;
  // Paged, shaded: read the pages the primary rays missed while the shadow and AO rays trace (Tracer::read_ahead).
  // Unset: where the device does not trace on the host's cores (GPUs). On the 2-core CPU devices measured, the
  // reading thread took cores from the tracing: shaded flight frames 5 % slower with it (BENCHMARKS.md).
  std::optional<bool> read_ahead;
  // Shade with the file's voxel colours (shaded and colour shadings) where the tracer has them: a voxel's own, or
  // at a coarser level of detail the mean of the voxels below (docs/colour.md). Off: grey.
  bool colours = true;
  // Camera rays start where a coarse pass over tiles of pixels proves nothing is hit before (the beam pre-pass,
  // kernels/common/trace_beam.h): the same picture in fewer steps. Paged tracers build its grid through the cache.
  bool beam = true;
};

// Whether a frame with these options shows voxel colours, where the model has them.
bool frame_uses_colours(const RenderOptions& options);

struct RenderPass {
  std::string name;   // "primary", "colour" (the hits' colours), "shadow", "ao"
  uint64_t rays = 0;  // rays traced (secondary passes: one per hit and sample)
  double seconds = 0;
};

struct RenderResult {
  Image image;
  std::vector<RenderPass> passes;  // of each tile's last pass
  uint64_t hits = 0;  // pixels whose primary ray hit
  // Cells the primary rays visited (descents and moves), all of them and those of the rays that hit: what a
  // primary ray costs, and what the beam pre-pass saves (RenderOptions::beam).
  uint64_t primary_steps = 0, hit_steps = 0;
  // Paged tracers: one update per pass; converged when every tile's last pass met no missing page, so the
  // picture equals the resident render's. A frame is one tile unless its per-pixel device buffers (60 bytes a
  // pixel shaded, 24 otherwise, 4 more with colours) exceed the device budget left beside the cache and the DAG, or its pages
  // exceed the cache: then bands of rows that fit, halved until their pages fit too (render.cpp).
  std::vector<CacheUpdateStats> cache;
  uint32_t beam_grid_passes = 0;  // paged: passes that built the beam pre-pass's grid (once per scene and size)
  bool converged = true;
  uint32_t tiles = 0;
  uint64_t coarse_pixels = 0;  // primary hits of the tiles' last passes that stopped at a missing page
  double trace_seconds = 0;    // all frame passes' tracing
};

// A camera flight: {"fov": F, "frames": [{"eye": [x,y,z], "target": [x,y,z], "up": [x,y,z]}, ...]} in model
// units (fov: degrees, default 40; up: default 0,1,0). Throws mv::Error naming the file and the frame.
std::vector<Camera> read_flight(const std::string& path);
std::vector<Camera> parse_flight(const std::string& text, const std::string& name);

// Renders on the tracer's device.
RenderResult render(Tracer& tracer, const Camera& camera, const RenderOptions& options);

// The same picture from the CPU reference: the flat voxel DDA (host/ref/trace_reference.h) over the decoded
// voxels of `file`, the same rays and the same shading. Slow; for tests.
RenderResult render_reference(const MvxFile& file, const Camera& camera, const RenderOptions& options);


}  // namespace mv
