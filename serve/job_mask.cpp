// A mask job: GrabCut of a photograph or range map from a box, a seed map and/or a model, with the library's
// masking as `megavox mask apply` runs it, written as a one-channel PNG (0 background, 255 foreground).
#include "io/image_reader.h"
#include "io/mvm_file.h"
#include "io/png_grey.h"
#include "megavox/error.h"
#include "megavox/mask.h"
#include "device_access.h"
#include "job_run.h"

namespace mv::serve {

void run_mask(MvDevice dev, const JobRun& run) {
  const JobRequest& r = run.request;
  run.progress("read", 0);
  const RasterImage image = io::read_image(run.input);
  MaskStart start;
  if (r.rect) {
    // checked here, where the image's size is known, to name the job's key rather than the library's box
    const auto [x, y, w, h] = *r.rect;
    if (uint64_t{x} + w > image.width || uint64_t{y} + h > image.height)
      throw Error("job: \"rect\" [" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(w) + ", " +
                  std::to_string(h) + "] reaches past the " + std::to_string(image.width) + " x " +
                  std::to_string(image.height) + " image");
    start.box = MaskBox{x, y, w, h};
  }
  if (!run.seeds.empty()) start.seeds = io::read_seed_map(run.seeds, image.width, image.height);
  MaskModel model;
  if (!run.model.empty()) {
    model = io::read_mvm(run.model);
    start.model = &model;
  }
  MaskOptions o;
  o.iterations = r.iterations;
  o.erode_radius = r.erode;
  run.progress("mask", 0.1);
  MaskResult m;
  on_device(dev, [&](Device& device, uint64_t) { m = mask_image(device, image, start, o); });
  run.progress("write", 0.9);
  io::write_png_grey(run.result, image.width, image.height, m.mask);
}

}  // namespace mv::serve
