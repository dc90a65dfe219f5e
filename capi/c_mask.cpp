// The C API: masks (GrabCut of an image file from a box, a seed map and/or a model, post-processed, written as
// a one-channel PNG), as a call and as a job.
#include <algorithm>
#include <cstring>
#include <memory>
#include <optional>

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

// seeds_in_memory: the call has a seed map of its own (mvMaskImage), a start beside those in args.
MaskFile mask_file(MvDevice device, const char* input, const char* output, const MvMaskArguments* args,
                   bool seeds_in_memory = false) {
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
  require(m.box || seeds_in_memory || !m.seeds.empty() || !m.model.empty(),
          "mask: no start: give a box, a seed map or a model");
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

// GrabCut and post-processing of `image` from m's box, `seeds` (a map in memory; else m.seeds' file) and m's model.
MaskResult mask_raster(MvDevice device, const MaskFile& m, const RasterImage& image, std::vector<uint8_t> seeds,
                       const Progress& progress) {
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
  if (!seeds.empty()) start.seeds = std::move(seeds);
  else if (!m.seeds.empty()) start.seeds = io::read_seed_map(m.seeds, image.width, image.height);
  MaskModel model;
  if (!m.model.empty()) {
    model = io::read_mvm(m.model);
    start.model = &model;
  }
  if (progress) progress("mask", 0);
  std::lock_guard<std::recursive_mutex> g(device->lock);
  return mask_image(*device->device, image, start, m.options);
}

void run_mask(MvDevice device, const MaskFile& m, const Progress& progress) {
  const std::string output = io::resolve_output({m.output, io::OutputKind::kFile, "png", {m.input, m.seeds, m.model}});
  if (progress) progress("read", 0);
  const RasterImage image = io::read_image(m.input);
  const MaskResult r = mask_raster(device, m, image, {}, progress);
  if (progress) progress("write", 0);
  io::write_png_grey(output, image.width, image.height, r.mask);
}

// The caller's pixels as a RasterImage (samples widened to 16 bits, as the file readers hold them).
RasterImage raster_of(const MvImageView* v, const char* what) {
  require(v, (std::string(what) + ": image is NULL").c_str());
  require(v->pixels, (std::string(what) + ": image.pixels is NULL").c_str());
  if (v->channels != 1 && v->channels != 3)
    throw ApiError(MV_ERROR_INVALID_ARGUMENT, std::string(what) + ": image.channels is " + std::to_string(v->channels) +
                                                  ", not 1 (grey, range) or 3 (R, G, B)");
  if (v->bytesPerSample != 1 && v->bytesPerSample != 2)
    throw ApiError(MV_ERROR_INVALID_ARGUMENT, std::string(what) + ": image.bytesPerSample is " +
                                                  std::to_string(v->bytesPerSample) + ", not 1 or 2");
  require(v->width > 0 && v->height > 0, (std::string(what) + ": the image is empty").c_str());
  if (uint64_t{v->width} * v->height > SIZE_MAX / 8)
    throw ApiError(MV_ERROR_INVALID_ARGUMENT, std::string(what) + ": the image's size overflows");
  const size_t row = size_t{v->width} * v->channels * v->bytesPerSample;
  const size_t stride = v->rowStride ? v->rowStride : row;
  require(stride >= row, (std::string(what) + ": image.rowStride is shorter than a row").c_str());
  RasterImage image;
  image.width = v->width;
  image.height = v->height;
  image.channels = v->channels;
  image.max_value = v->bytesPerSample == 1 ? 255 : 65535;
  image.samples.resize(size_t{v->width} * v->height * v->channels);
  const auto* bytes = static_cast<const uint8_t*>(v->pixels);
  const size_t per_row = size_t{v->width} * v->channels;
  for (uint32_t y = 0; y < v->height; ++y) {
    const uint8_t* r = bytes + y * stride;
    uint16_t* out = image.samples.data() + y * per_row;
    if (v->bytesPerSample == 1) std::copy(r, r + per_row, out);
    else std::memcpy(out, r, per_row * 2);
  }
  return image;
}

void mask_memory(MvDevice device, const MvImageView* image, const uint8_t* seeds, const MvMaskArguments* args,
                 uint8_t* mask) {
  require(device, "mask: no device");
  require(mask, "mask: mask is NULL");
  require(args, "mask: args is NULL (call mvInitMaskArguments and give a start)");
  // The start is checked as for a file, with this call's names standing for the paths.
  MvMaskArguments a = *args;
  if (seeds) a.seeds = nullptr;
  const RasterImage raster = raster_of(image, "mask");
  std::vector<uint8_t> seed_map;
  if (seeds) seed_map.assign(seeds, seeds + size_t{raster.width} * raster.height);
  for (size_t i = 0; i < seed_map.size(); ++i) {
    const uint8_t s = seed_map[i];
    if (s != 0 && s != 64 && s != 128 && s != 192 && s != 255)
      throw ApiError(MV_ERROR_INVALID_ARGUMENT, "mask: seed map pixel (" + std::to_string(i % raster.width) + ", " +
                                                    std::to_string(i / raster.width) + ") is " + std::to_string(s) +
                                                    ", not one of 0, 64, 128, 192, 255");
  }
  const MaskFile m = mask_file(device, "image in memory", "mask in memory", &a, seeds != nullptr);
  if (m.user) m.user("read", 0);
  const MaskResult r = mask_raster(device, m, raster, std::move(seed_map), m.user);
  std::memcpy(mask, r.mask.data(), r.mask.size());
}

void train_model(MvDevice device, const MvImageView* images, const uint8_t* const* masks, size_t count,
                 const char* output) {
  require(device, "mask train: no device");
  require(output && *output, "mask train: no output path");
  require(count > 0, "mask train: no image");
  require(images && masks, "mask train: images or masks is NULL");
  const std::string path = io::resolve_output({output, io::OutputKind::kFile, "mvm", {}});
  std::optional<MaskModel> model;
  for (size_t i = 0; i < count; ++i) {
    const std::string name = "mask train: image " + std::to_string(i);
    const RasterImage img = raster_of(&images[i], name.c_str());
    require(masks[i], (name + ": its mask is NULL").c_str());
    if (model && model->channels != img.channels)
      throw ApiError(MV_ERROR_INVALID_ARGUMENT, name + " has " + std::to_string(img.channels) +
                                                    " channels, the images before it " + std::to_string(model->channels));
    if (!model) model = MaskModel::empty(img.channels);
    const size_t n = size_t{img.width} * img.height;
    const std::vector<uint16_t> mk(masks[i], masks[i] + n);
    model->train(img, mk, img.width, img.height);
  }
  uint64_t fg = 0, bg = 0;
  for (uint32_t b = 0; b < model->bins(); ++b) fg += model->fg[b], bg += model->bg[b];
  if (fg == 0 || bg == 0)
    throw ApiError(MV_ERROR_INPUT, std::string("mask train: the masks hold no ") +
                                       (fg == 0 ? "foreground (255)" : "background (0)") + " pixel");
  io::write_mvm(path, *model);
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

MvError mvMaskImage(MvDevice device, const MvImageView* image, const uint8_t* seeds, const MvMaskArguments* args,
                    uint8_t* mask) {
  return guard(device, [&] { mask_memory(device, image, seeds, args, mask); });
}

MvError mvTrainMaskModel(MvDevice device, const MvImageView* images, const uint8_t* const* masks, size_t count,
                         const char* output) {
  return guard(device, [&] { train_model(device, images, masks, count, output); });
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
