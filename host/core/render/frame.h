// What the device renderer and the CPU reference renderer share: the camera and secondary-ray setup in
// root-cube coordinates, and the shading of per-pixel trace results into an image.
#pragma once
#include <cstdint>
#include <vector>

#include "common/secondary.h"
#include "megavox/render.h"

namespace mv {

struct FrameSetup {
  uint32_t width = 0, height = 0, levels = 0;
  float camera[MV_CAMERA_FLOATS] = {};  // kernels/common/trace_types.h: mv_camera_ray
  float proj = 0;                        // LOD factor
  MvSecondaryParams shadow{};            // kind, light direction, tmax
  MvSecondaryParams ao{};                // kind, stride, mask, radius (sample_k set per pass)
  uint32_t ao_samples = 0;
  std::vector<float> ao_table;           // cosine-weighted directions around +z, 3 floats each
};

FrameSetup frame_setup(const GridTransform& grid, uint32_t levels, const Camera& camera, const RenderOptions& options);

// The beam pre-pass's grids for a frame (kernels/common/trace_beam.h, TraceEngine::beam), for its tiles and for
// the parent pass's tiles twice as wide: `reach`, how far a tile's rays stray from its centre ray per unit t, and
// the finest grid (cells per axis) whose proof still holds at the depth of the root cube's centre; cells = 0
// where even 4 cells per axis are too fine (no parent pass, or no beam).
struct BeamSetup {
  uint32_t cells = 0, parent_cells = 0;
  float reach = 0, parent_reach = 0;
};
BeamSetup beam_setup(const FrameSetup& setup, uint32_t max_cells);

// Per-pixel trace results: hit records (MV_HIT_WORDS each), occlusion counts and the hits' colours (R | G << 8 |
// B << 16 | A << 24, kernels/common/trace_colour.h), each empty when not traced.
struct FrameResults {
  std::vector<uint32_t> hits, shadow, ao, colours;
};

Image shade(const FrameSetup& setup, const RenderOptions& options, const FrameResults& results);

}  // namespace mv
