// megavox.mask: GrabCut masks of images in memory, and mask models trained on them.
#include <vector>

#include "devices.h"

namespace megavox_py {

namespace {

// An image array (uint8 or uint16; (h, w), (h, w, 1) or (h, w, 3)) kept C-contiguous while the view is used.
struct ImageArg {
  py::array pixels;
  MvImageView view{};
};

ImageArg image_arg(const py::handle& obj, const std::string& name) {
  if (!py::isinstance<py::array>(obj)) bad_argument(name + ": a numpy array of shape (h, w) or (h, w, 3) is expected");
  py::array a = py::reinterpret_borrow<py::array>(obj);
  const bool u8 = a.dtype().equal(py::dtype::of<uint8_t>()), u16 = a.dtype().equal(py::dtype::of<uint16_t>());
  if (!u8 && !u16) bad_argument(name + ": dtype " + dtype_name(a) + " where uint8 or uint16 is expected");
  const bool shaped = a.ndim() == 2 || (a.ndim() == 3 && (a.shape(2) == 1 || a.shape(2) == 3));
  if (!shaped || a.shape(0) == 0 || a.shape(1) == 0)
    bad_argument(name + ": shape (h, w), (h, w, 1) or (h, w, 3) with h, w > 0 is expected");
  if (a.shape(0) > 0xffffffffLL || a.shape(1) > 0xffffffffLL) bad_argument(name + ": over 2^32 - 1 rows or columns");
  ImageArg out;
  out.pixels = u8 ? py::array(contiguous<uint8_t>(a))
                  : py::array(contiguous<uint16_t>(a));
  out.view.pixels = out.pixels.data();
  out.view.height = static_cast<uint32_t>(a.shape(0));
  out.view.width = static_cast<uint32_t>(a.shape(1));
  out.view.channels = a.ndim() == 3 ? static_cast<uint32_t>(a.shape(2)) : 1;
  out.view.bytesPerSample = u8 ? 1 : 2;
  return out;
}

// A (h, w) uint8 map the size of `image`.
py::array_t<uint8_t, py::array::c_style> plane_arg(const py::handle& obj, const MvImageView& image, const std::string& name) {
  if (!py::isinstance<py::array>(obj)) bad_argument(name + ": a uint8 numpy array of shape (h, w) is expected");
  const py::array a = py::reinterpret_borrow<py::array>(obj);
  if (!a.dtype().equal(py::dtype::of<uint8_t>())) bad_argument(name + ": dtype " + dtype_name(a) + " where uint8 is expected");
  if (a.ndim() != 2 || size_t(a.shape(0)) != image.height || size_t(a.shape(1)) != image.width)
    bad_argument(name + ": shape (" + std::to_string(image.height) + ", " + std::to_string(image.width) +
                 ") (the image's) is expected");
  return contiguous<uint8_t>(a);
}

py::array_t<uint8_t> apply(const Device& device, const py::object& image_obj, const py::object& rect,
                           const py::object& seeds, const py::object& model, uint32_t iterations, uint32_t erode,
                           const py::object& progress_fn) {
  const MvDevice d = device.get();
  const ImageArg image = image_arg(image_obj, "image");
  Progress progress(progress_fn);
  MvMaskArguments args;
  mvInitMaskArguments(&args);
  args.iterations = iterations;
  args.erode = erode;
  args.progress = progress.function();
  args.progressUserPtr = progress.user();
  if (!rect.is_none()) {
    if (!py::isinstance<py::sequence>(rect)) bad_argument("rect: (x, y, width, height) is expected");
    const py::sequence r = rect.cast<py::sequence>();
    if (r.size() != 4) bad_argument("rect: (x, y, width, height) is expected");
    args.hasRect = true;
    for (int k = 0; k < 4; ++k) {
      if (!PyIndex_Check(r[k].ptr()))
        bad_argument("rect: " + py::repr(r[k]).cast<std::string>() + " is not a whole number of pixels");
      const py::object v = py::module_::import("operator").attr("index")(r[k]);
      if (v.attr("__lt__")(0).cast<bool>() || v.attr("__gt__")(py::int_(0xffffffffu)).cast<bool>())
        bad_argument("rect: " + py::str(v).cast<std::string>() + " is not a pixel count");
      args.rect[k] = v.cast<uint32_t>();
    }
  }
  std::optional<py::array_t<uint8_t, py::array::c_style>> seed_map;
  if (!seeds.is_none()) seed_map = plane_arg(seeds, image.view, "seeds");
  std::string model_path;
  if (!model.is_none()) {
    model_path = fspath(model);
    args.model = model_path.c_str();
  }
  if (rect.is_none() && seeds.is_none() && model.is_none()) bad_argument("mask: give rect, seeds or model (a start)");
  py::array_t<uint8_t> mask({py::ssize_t(image.view.height), py::ssize_t(image.view.width)});
  uint8_t* out = mask.mutable_data();
  MvError e;
  {
    py::gil_scoped_release nogil;
    e = mvMaskImage(d, &image.view, seed_map ? seed_map->data() : nullptr, &args, out);
  }
  progress.check(d, e);
  return mask;
}

void train(const Device& device, const py::sequence& images, const py::sequence& masks, const py::object& out) {
  const MvDevice d = device.get();
  if (images.size() != masks.size())
    bad_argument("images, masks: " + std::to_string(images.size()) + " images and " + std::to_string(masks.size()) + " masks");
  std::vector<ImageArg> views;
  std::vector<py::array_t<uint8_t, py::array::c_style>> planes;
  for (size_t i = 0; i < images.size(); ++i) {
    views.push_back(image_arg(images[i], "images[" + std::to_string(i) + "]"));
    planes.push_back(plane_arg(masks[i], views.back().view, "masks[" + std::to_string(i) + "]"));
  }
  std::vector<MvImageView> v;
  std::vector<const uint8_t*> m;
  for (size_t i = 0; i < views.size(); ++i) {
    v.push_back(views[i].view);
    m.push_back(planes[i].data());
  }
  const std::string path = fspath(out);
  MvError e;
  {
    py::gil_scoped_release nogil;
    e = mvTrainMaskModel(d, v.data(), m.data(), v.size(), path.c_str());
  }
  check(d, e);
}

}  // namespace

void bind_masks(py::module_& m) {
  m.def("_mask_apply", &apply, py::arg("device"), py::arg("image"), py::arg("rect"), py::arg("seeds"), py::arg("model"),
        py::arg("iterations"), py::arg("erode"), py::arg("progress"));
  m.def("_mask_train", &train, py::arg("device"), py::arg("images"), py::arg("masks"), py::arg("out"));
}

}  // namespace megavox_py
