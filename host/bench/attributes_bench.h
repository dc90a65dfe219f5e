// `megavox bench attributes`: what voxel colours cost and save on a coloured cloud. The same cloud built without
// colour (--attributes none), then with colour at each quantization (24 = lossless), each best of `repeats`
// with kernels already compiled; the colour section's bits per voxel against raw storage, the thesis's
// compression rate, ΔE94; build stages (read and write excluded) and host peak memory against the colourless
// build; and the shaded render of the coloured file with and without its colours.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "megavox/build.h"
#include "megavox/device.h"
#include "megavox/render.h"

namespace mv::bench {

struct AttributeBuild {
  uint32_t bits = 24;           // --colour-bits (0: the colourless build)
  BuildReport report;           // of the fastest run
  double stage_seconds = 0;     // the fastest run's stages, read and write excluded
  uint64_t peak_rss_bytes = 0;  // this process's peak over the runs (reset before them where Linux allows)
  uint64_t colour_bytes = 0;    // the colour section, head included
  double colour_bits_per_voxel = 0, raw_bits_per_voxel = 0;  // raw: 24 bits an entry, head included
  double compression_rate = 0;  // the section's bytes / the raw attribute array's (3 bytes an entry)
};

struct AttributesBenchResult {
  std::string input;
  uint64_t points = 0, triangles = 0, voxels = 0, entries = 0;  // points: a cloud's; triangles: a mesh's
  AttributeBuild colourless;
  std::vector<AttributeBuild> coloured;  // one per --bits
  // The 24-bit file rendered shaded at the render size, best of `repeats`: with its colours and grey.
  double render_seconds = 0, grey_render_seconds = 0, colour_pass_seconds = 0;
  uint64_t hits = 0, pixels_changed = 0;  // hit pixels; those whose colour differs from the grey render's
  bool peak_rss_reset = false;
};

struct AttributesBenchOptions {
  uint32_t resolution = 1024;
  std::vector<uint32_t> bits = {24, 14, 12};
  uint32_t repeats = 3;
  RenderOptions render;  // width, height, samples
};

AttributesBenchResult bench_attributes(Device& dev, const std::string& cloud, const AttributesBenchOptions& options);

}  // namespace mv::bench
