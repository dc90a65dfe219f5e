// megavox — masks of photographs and range maps on a device: GrabCut whose min-cuts run as kernels
// (min_cut.h), then the thesis's post-processing (a 5x5 median and an octagon erosion, as kernels).
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "megavox/device.h"
#include "megavox/mask_model.h"
#include "megavox/min_cut.h"
#include "megavox/raster.h"

namespace mv {

struct MaskBox {
  uint32_t x = 0, y = 0, w = 0, h = 0;
};

// Where GrabCut starts: any of a box (outside sure background, inside probable foreground), a seed map
// (0 / 64 / 128 / 192 / 255 = sure bg / probable bg / unknown / probable fg / sure fg) and a model
// (probable foreground above 0.5). Seeds override the box and the model where they say anything but 128; a
// model decides inside the box when both are given.
struct MaskStart {
  std::optional<MaskBox> box;
  std::vector<uint8_t> seeds;  // empty: none
  const MaskModel* model = nullptr;
};

struct MaskOptions {
  uint32_t iterations = 5;
  bool post = true;            // median and erosion
  uint32_t erode_radius = 2;   // octagon inradius in pixels (0: no erosion)
  MinCutSolver min_cut_solver = MinCutSolver::automatic;  // every solver gives the same cuts: only the time moves
};

struct MaskResult {
  std::vector<uint8_t> grabcut;  // GrabCut's labelling, 0 / 255
  std::vector<uint8_t> mask;     // after post-processing (= grabcut with post off), 0 / 255
  uint32_t iterations = 0;
  uint64_t cut_value = 0;        // the last cut, in quantized units
  double foreground = 0;         // share of mask pixels at 255
};

// Throws mv::Error on a start that does not fit the image (box outside, seed map of another size, model of the
// other channel count) or leaves a side without pixels.
MaskResult mask_image(Device& dev, const RasterImage& image, const MaskStart& start, const MaskOptions& options = {});

// The start labels (host/core/mask/grabcut.h's Label values) of a start.
std::vector<uint8_t> start_labels(const RasterImage& image, const MaskStart& start);

// Median then erosion of a 0 / non-zero mask on the device; 0 / 255 out.
std::vector<uint8_t> postprocess_mask(Device& dev, const std::vector<uint8_t>& mask, uint32_t width, uint32_t height,
                                      uint32_t erode_radius);

}  // namespace mv
