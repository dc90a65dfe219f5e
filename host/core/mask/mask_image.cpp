// A mask from a start: start labels (box, seeds, model), GrabCut with the device min-cut, post-processing.
#include <string>

#include "grabcut.h"
#include "megavox/error.h"
#include "megavox/mask.h"
#include "megavox/min_cut.h"

namespace mv {

std::vector<uint8_t> start_labels(const RasterImage& image, const MaskStart& start) {
  using namespace mask;
  const uint32_t W = image.width, H = image.height;
  const size_t n = size_t{W} * H;
  if (!start.box && start.seeds.empty() && !start.model)
    throw CodedError(ErrorCode::invalid_argument, "mask: no start: give a box, a seed map or a model");
  std::vector<uint8_t> labels(n, kUnknown);
  if (start.box) labels = box_labels(W, H, start.box->x, start.box->y, start.box->w, start.box->h);
  if (start.model) {
    if (start.model->channels != image.channels)
      throw Error("mask: the model is for " + std::to_string(start.model->channels) + "-channel images, the image has " +
                  std::to_string(image.channels) + " channel" + (image.channels == 1 ? "" : "s"));
    for (size_t i = 0; i < n; ++i)
      if (labels[i] != kBackground)  // inside the box, or everywhere without one
        labels[i] = start.model->probability(image, i) > 0.5 ? kProbableForeground : kProbableBackground;
  }
  if (!start.seeds.empty()) {
    if (start.seeds.size() != n) throw Error("mask: the seed map does not match the image's size");
    for (size_t i = 0; i < n; ++i) switch (start.seeds[i]) {
        case 0: labels[i] = kBackground; break;
        case 64: labels[i] = kProbableBackground; break;
        case 192: labels[i] = kProbableForeground; break;
        case 255: labels[i] = kForeground; break;
        case 128: break;  // unconstrained: what the box or the model said, else unknown
        default: throw Error("mask: seed value " + std::to_string(start.seeds[i]) + " (0, 64, 128, 192, 255)");
      }
  }
  return labels;
}

MaskResult mask_image(Device& dev, const RasterImage& image, const MaskStart& start, const MaskOptions& options) {
  mask::GrabCutOptions go;
  go.iterations = options.iterations;
  MinCutFlow flow;  // GrabCut's iterations keep the edges: each cut starts from the last one's flow
  MinCutOptions cut_options;
  cut_options.solver = options.min_cut_solver;
  const mask::GrabCutResult gc = mask::grabcut(dev, image, start_labels(image, start), go, [&](const GridGraph& g) {
    return min_cut(dev, g, cut_options, nullptr, &flow);
  });
  MaskResult r;
  r.grabcut = mask::labels_to_mask(gc.labels);
  r.mask = options.post ? postprocess_mask(dev, r.grabcut, image.width, image.height, options.erode_radius) : r.grabcut;
  r.iterations = gc.iterations;
  r.cut_value = gc.cut_value;
  size_t ones = 0;
  for (uint8_t v : r.mask) ones += v != 0;
  r.foreground = r.mask.empty() ? 0.0 : static_cast<double>(ones) / static_cast<double>(r.mask.size());
  return r;
}

}  // namespace mv
