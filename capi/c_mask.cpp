// The C API: masks (GrabCut of an image file from a box, a seed map and/or a model, post-processed, written as
// a one-channel PNG), as a call and as a job.
#include <memory>

#include "job.h"
#include "io/image_reader.h"
#include "io/mvm_file.h"
#include "io/output_path.h"
#include "io/png_grey.h"
#include "megavox/mask.h"

namespace mv::capi {

namespace {

struct MaskFile {
  std::string input, output, seeds, model;
  std::optional<MaskBox> box;
  MaskOptions options;
  Progress user;
};

MaskFile mask_file(MvDevice device, const char* input, const char* output, const MvMaskArguments* args) {
  require(device, "mask: no device");
  require(input && *input, "mask: no input path");
  require(output && *output, "mask: no output path");
  require(args, "mask: args is NULL (call mvInitMaskArguments and give a start)");
  require(args->byteSize == sizeof(MvMaskArguments),
          "mask: MvMaskArguments.byteSize is wrong (call mvInitMaskArguments)");
  MaskFile m;
  m.input = input;
  m.output = output;
  if (args->hasRect) m.box = MaskBox{args->rect[0], args->rect[1], args->rect[2], args->rect[3]};
  m.seeds = args->seeds ? args->seeds : "";
  m.model = args->model ? args->model : "";
  require(m.box || !m.seeds.empty() || !m.model.empty(), "mask: no start: give a box, a seed map or a model");
  m.options.iterations = args->iterations;
  m.options.erode_radius = args->erode;
  m.user = user_progress(args->progress, args->progressUserPtr, "mask");
  return m;
}

// Reading the image, GrabCut and post-processing on the device, writing: about their shares of the time.
double mask_overall(const std::string& stage, double f) {
  if (stage == "read") return 0.1 * f;
  if (stage == "mask") return 0.1 + 0.8 * f;
  if (stage == "write") return 0.9 + 0.1 * f;
  return 0;
}

void run_mask(MvDevice device, const MaskFile& m, const Progress& progress) {
  const auto report = [&](const char* stage, double f) {
    if (progress) progress(stage, f);
  };
  const std::string output = io::resolve_output({m.output, io::OutputKind::kFile, "png", {m.input, m.seeds, m.model}});
  report("read", 0);
  const RasterImage image = io::read_image(m.input);
  MaskStart start;
  if (m.box) {
    // named as the caller gave it, before the library's own check, which speaks of labels
    const auto [x, y, w, h] = *m.box;
    if (uint64_t{x} + w > image.width || uint64_t{y} + h > image.height)
      throw ApiError(MV_ERROR_INVALID_ARGUMENT,
                     "mask: the box [" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(w) +
                         ", " + std::to_string(h) + "] reaches past the " + std::to_string(image.width) + " x " +
                         std::to_string(image.height) + " image");
    start.box = m.box;
  }
  if (!m.seeds.empty()) start.seeds = io::read_seed_map(m.seeds, image.width, image.height);
  MaskModel model;
  if (!m.model.empty()) {
    model = io::read_mvm(m.model);
    start.model = &model;
  }
  report("mask", 0);
  MaskResult r;
  {
    std::lock_guard<std::recursive_mutex> g(device->lock);
    r = mask_image(*device->device, image, start, m.options);
  }
  report("write", 0);
  io::write_png_grey(output, image.width, image.height, r.mask);
}

}  // namespace

}  // namespace mv::capi

using namespace mv::capi;

extern "C" {

void mvInitMaskArguments(MvMaskArguments* args) {
  if (!args) return;
  const mv::MaskOptions d;
  *args = MvMaskArguments{};
  args->byteSize = sizeof(MvMaskArguments);
  args->iterations = d.iterations;
  args->erode = d.erode_radius;
}

MvError mvMaskImageFile(MvDevice device, const char* input, const char* output, const MvMaskArguments* args) {
  return guard(device, [&] {
    const MaskFile m = mask_file(device, input, output, args);
    run_mask(device, m, m.user);
  });
}

MvJob mvMaskImageFileAsync(MvDevice device, const char* input, const char* output, const MvMaskArguments* args) {
  MvJob job = nullptr;
  guard(device, [&] {
    auto m = std::make_shared<MaskFile>(mask_file(device, input, output, args));
    JobWork work;
    work.run = [device, m](const mv::Progress& progress) -> MvScene {
      run_mask(device, *m, progress);
      return nullptr;
    };
    work.overall = mask_overall;
    work.user = m->user;
    job = start_job(device, std::move(work));
  });
  return job;
}

}  // extern "C"
