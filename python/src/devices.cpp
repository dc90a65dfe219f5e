// megavox.devices(), megavox.Device and megavox.write_image.
#include <memory>
#include <vector>

#include "devices.h"

namespace megavox_py {

namespace {

// A size as the device config takes it: an int of bytes, or text such as "512M".
std::string size_text(const py::handle& v, const char* key) {
  if (py::isinstance<py::bool_>(v)) bad_argument(std::string(key) + ": a size in bytes or text such as \"512M\"");
  if (py::isinstance<py::int_>(v)) {
    const std::string n = py::str(v).cast<std::string>();  // any size: the C API refuses what is too large
    if (v.attr("__le__")(0).cast<bool>()) bad_argument(std::string(key) + ": " + n + " is not a positive size");
    return n;
  }
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  bad_argument(std::string(key) + ": a size in bytes or text such as \"512M\", not " +
               py::str(py::type::of(v)).cast<std::string>());
}

std::unique_ptr<Device> open_device(const py::object& selector, const py::object& memory, const py::object& host_memory,
                                    const py::object& cache_memory, const py::object& kernel_shape) {
  std::vector<std::pair<std::string, std::string>> items;
  auto text = [](const py::object& v, const char* key) {
    if (!py::isinstance<py::str>(v))
      bad_argument(std::string(key) + ": text is expected (" + (std::string(key) == "selector" ? "\"ocl:0\", \"vk:0\" or part of a name" : "auto, gpu or cpu") + ")");
    return v.cast<std::string>();
  };
  if (!selector.is_none()) items.emplace_back("device", text(selector, "selector"));
  if (!memory.is_none()) items.emplace_back("memory", size_text(memory, "memory"));
  if (!host_memory.is_none()) items.emplace_back("host_memory", size_text(host_memory, "host_memory"));
  if (!cache_memory.is_none()) items.emplace_back("cache_memory", size_text(cache_memory, "cache_memory"));
  if (!kernel_shape.is_none()) items.emplace_back("kernel_shape", text(kernel_shape, "kernel_shape"));
  std::string config;
  for (const auto& [k, v] : items) {
    if (v.find(',') != std::string::npos) bad_argument(k + ": '" + v + "' holds a comma");
    config += (config.empty() ? "" : ",") + k + "=" + v;
  }
  MvDevice d;
  {
    py::gil_scoped_release nogil;  // opening compiles or loads kernels
    d = mvNewDevice(config.c_str());
  }
  if (!d) check(nullptr, failure_code(nullptr));
  watch_errors(d);
  return std::make_unique<Device>(d);
}

py::dict device_info(const Device& self) {
  MvDeviceInfo i;
  check(self.get(), nogil([&] { return mvGetDeviceInfo(self.get(), &i); }));
  const uint64_t host = nogil([&] { return mvGetHostMemoryBudget(self.get()); });
  py::dict out;
  out["name"] = std::string(i.name);
  out["backend"] = std::string(i.backend);
  out["selector"] = std::string(i.selector);
  out["memory_budget"] = i.memoryBudget;
  out["memory_used"] = i.memoryUsed;
  out["host_memory_budget"] = host;
  return out;
}

py::list devices() {
  std::vector<MvDeviceDescription> all;
  {
    py::gil_scoped_release nogil;
    mvGetDeviceError(nullptr);  // an older error of this thread is not this call's
    const size_t n = mvListDevices(nullptr, 0);
    all.resize(n);
    if (n) all.resize(mvListDevices(all.data(), n));
  }
  const MvError e = mvGetDeviceError(nullptr);
  if (e != MV_ERROR_NONE) raise(e, mvGetDeviceLastErrorMessage(nullptr));
  py::list out;
  for (const MvDeviceDescription& d : all) {
    py::dict item;
    item["selector"] = std::string(d.selector);
    item["name"] = std::string(d.name);
    item["backend"] = std::string(d.backend);
    item["type"] = std::string(d.type);
    item["platform"] = std::string(d.platform);
    item["memory_bytes"] = d.memoryBytes;
    item["default"] = d.isDefault;
    out.append(item);
  }
  return out;
}

void write_image(const py::object& path_obj, const py::handle& rgba) {
  const std::string path = fspath(path_obj);
  if (!py::isinstance<py::array>(rgba)) bad_argument("rgba: a numpy array of shape (height, width, 4) is expected");
  const py::array a = py::reinterpret_borrow<py::array>(rgba);
  if (a.ndim() != 3 || (a.shape(2) != 4 && a.shape(2) != 3) || !a.dtype().equal(py::dtype::of<uint8_t>()))
    bad_argument("rgba: a uint8 array of shape (height, width, 4) or (height, width, 3) is expected, not " +
                 dtype_name(a) + " of " + std::to_string(a.ndim()) + " dimensions");
  if (a.shape(0) > 0xffffffffLL || a.shape(1) > 0xffffffffLL) bad_argument("rgba: over 2^32 - 1 rows or columns");
  const auto h = static_cast<uint32_t>(a.shape(0)), w = static_cast<uint32_t>(a.shape(1));
  auto pixels = contiguous<uint8_t>(a);
  std::vector<uint8_t> four;
  const uint8_t* data = pixels.data();
  if (a.shape(2) == 3) {  // alpha is dropped by the writer anyway
    four.resize(size_t{w} * h * 4, 255);
    for (size_t i = 0; i < size_t{w} * h; ++i)
      for (int c = 0; c < 3; ++c) four[4 * i + c] = data[3 * i + c];
    data = four.data();
  }
  MvError e;
  {
    py::gil_scoped_release nogil;
    e = mvWriteImage(path.c_str(), data, w, h, 0);
  }
  check(nullptr, e);
}

}  // namespace

void bind_devices(py::module_& m) {
  m.def("devices", &devices, "Every OpenCL and Vulkan device: a list of dicts (selector, name, backend, type, "
                             "platform, memory_bytes, default).");
  m.def("write_image", &write_image, py::arg("path"), py::arg("rgba"),
        "Writes (height, width, 4) or (height, width, 3) uint8 pixels as a PNG, or a JPEG for .jpg / .jpeg.");
  py::class_<Device>(m, "Device", "A compute device: every call on it is serialised; scenes keep it alive.")
      .def(py::init(&open_device), py::arg("selector") = py::none(), py::kw_only(), py::arg("memory") = py::none(),
           py::arg("host_memory") = py::none(), py::arg("cache_memory") = py::none(),
           py::arg("kernel_shape") = py::none())
      .def_property_readonly("info", &device_info)
      .def("__repr__", [](const Device& self) {
        MvDeviceInfo i;
        if (nogil([&] { return mvGetDeviceInfo(self.get(), &i); }) != MV_ERROR_NONE) return std::string("<megavox.Device>");
        return "<megavox.Device " + std::string(i.selector) + ": " + i.name + ">";
      });
}

}  // namespace megavox_py
