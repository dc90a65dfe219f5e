// Device.build / Device.open and megavox.Scene: voxel DAGs, ray queries and pictures.
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "devices.h"

namespace megavox_py {

namespace {

class Scene {
 public:
  Scene(MvScene s, py::object device) : s_(s), device_(std::move(device)) {}
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;
  ~Scene() { nogil([&] { mvReleaseScene(s_); }); }
  MvScene get() const { return s_; }
  MvDevice device() const { return device_.cast<const Device&>().get(); }
  const py::object& device_object() const { return device_; }

 private:
  MvScene s_;
  py::object device_;  // the megavox.Device (the scene also holds the MvDevice itself)
};

// A number argument (int, float, a numpy scalar) as double; anything else is refused naming `name`.
double number(const py::handle& v, const char* name) {
  if (py::isinstance<py::bool_>(v) || !PyNumber_Check(v.ptr()))
    bad_argument(std::string(name) + ": a number is expected, not " + py::str(py::type::of(v)).cast<std::string>());
  return py::float_(py::reinterpret_borrow<py::object>(v)).cast<double>();
}

std::string text_arg(const py::object& v, const char* name) {
  if (!py::isinstance<py::str>(v)) bad_argument(std::string(name) + ": text is expected");
  return v.cast<std::string>();
}

// Triangles as uint32: uint32 as is, other integer dtypes when every index fits (copied), anything else refused.
py::array_t<uint32_t, py::array::c_style> triangle_array(const py::handle& obj) {
  if (!py::isinstance<py::array>(obj)) bad_argument("triangles: a numpy array of shape (m, 3) is expected");
  py::array a = py::reinterpret_borrow<py::array>(obj);
  if (a.dtype().equal(py::dtype::of<uint32_t>())) return rows<uint32_t>(a, "triangles", 3);
  if (a.dtype().kind() != 'i' && a.dtype().kind() != 'u')
    bad_argument("triangles: dtype " + dtype_name(a) + " where an integer dtype (uint32 or int32) is expected");
  if (a.ndim() != 2 || a.shape(1) != 3) rows<uint32_t>(a.attr("astype")("uint32"), "triangles", 3);  // names the shape
  if (a.size() > 0) {
    const py::object lo = a.attr("min")(), hi = a.attr("max")();  // compared as Python ints: any width
    if (lo.attr("__lt__")(0).cast<bool>()) bad_argument("triangles: a negative index (" + py::str(lo).cast<std::string>() + ")");
    if (hi.attr("__gt__")(py::int_(0xffffffffu)).cast<bool>())
      bad_argument("triangles: index " + py::str(hi).cast<std::string>() + " does not fit 32 bits");
  }
  return rows<uint32_t>(a.attr("astype")("uint32"), "triangles", 3);
}

// Per-vertex colours, 3 bytes each: uint8 (n, 3) as is, (n, 4) without its alpha.
py::array_t<uint8_t, py::array::c_style> colour_array(const py::handle& obj, size_t vertices) {
  if (!py::isinstance<py::array>(obj)) bad_argument("colours: a uint8 numpy array of shape (n, 3) or (n, 4) is expected");
  py::array a = py::reinterpret_borrow<py::array>(obj);
  if (a.ndim() == 2 && a.shape(1) == 4) a = a.attr("__getitem__")(py::make_tuple(py::slice(py::none(), py::none(), py::none()), py::slice(0, 3, 1)));
  auto c = rows<uint8_t>(a, "colours", 3);
  if (size_t(c.shape(0)) != vertices)
    bad_argument("colours: " + std::to_string(c.shape(0)) + " colours for " + std::to_string(vertices) + " vertices");
  return c;
}

MvBuildArguments build_arguments(uint32_t resolution, const std::string& format, uint32_t cube,
                                 const std::string& voxelize, const std::string& grid_origin, const std::string& grid,
                                 const std::string& output, Progress& progress) {
  MvBuildArguments args;
  mvInitBuildArguments(&args);
  args.format = format.c_str();
  args.resolution = resolution;
  args.cube = cube;
  args.voxelize = voxelize.c_str();
  args.gridOrigin = grid_origin.c_str();
  args.grid = grid.empty() ? nullptr : grid.c_str();
  args.output = output.empty() ? nullptr : output.c_str();
  args.progress = progress.function();
  args.progressUserPtr = progress.user();
  return args;
}

std::unique_ptr<Scene> build(const py::object& self_obj, const py::object& source, uint32_t resolution,
                             const std::string& format, uint32_t cube, const std::string& voxelize,
                             const std::string& grid_origin, const py::object& grid, const py::object& output,
                             const py::object& progress_fn) {
  const MvDevice d = self_obj.cast<const Device&>().get();
  const std::string grid_name = grid.is_none() ? "" : text_arg(grid, "grid");
  const std::string out = output.is_none() ? "" : fspath(output);
  Progress progress(progress_fn);
  const MvBuildArguments args = build_arguments(resolution, format, cube, voxelize, grid_origin, grid_name, out, progress);
  MvScene s = nullptr;
  const auto keep = [&] { return std::make_unique<Scene>(s, self_obj); };  // owns the scene before any raise
  if (py::isinstance<py::tuple>(source) || py::isinstance<py::list>(source)) {
    const py::sequence parts = source.cast<py::sequence>();
    if (parts.size() != 2 && parts.size() != 3)
      bad_argument("source: (vertices, triangles) or (vertices, triangles, colours) is expected");
    const auto v = rows<float>(parts[0], "vertices", 3);
    const auto t = triangle_array(parts[1]);
    std::optional<py::array_t<uint8_t, py::array::c_style>> c;
    if (parts.size() == 3 && !parts[2].is_none()) c = colour_array(parts[2], v.shape(0));
    py::gil_scoped_release nogil;
    s = mvBuildSceneFromMemoryRgb(d, v.data(), v.shape(0), t.data(), t.shape(0), c ? c->data() : nullptr, &args);
  } else {
    const std::string path = fspath(source);
    py::gil_scoped_release nogil;
    s = mvBuildSceneFromFile(d, path.c_str(), &args);
  }
  if (!s) progress.check(d, failure_code(d));
  auto scene = keep();
  progress.check(d, MV_ERROR_NONE);  // what the callback raised, though the build finished
  return scene;
}

std::unique_ptr<Scene> open_scene(const py::object& self_obj, const py::object& path_obj) {
  const MvDevice d = self_obj.cast<const Device&>().get();
  const std::string path = fspath(path_obj);
  MvScene s;
  {
    py::gil_scoped_release nogil;
    s = mvOpenScene(d, path.c_str());
  }
  if (!s) check(d, failure_code(d));
  return std::make_unique<Scene>(s, self_obj);
}

py::tuple triple(const double* v) { return py::make_tuple(v[0], v[1], v[2]); }

py::dict scene_info(const Scene& self) {
  MvSceneInfo i;
  check(self.device(), nogil([&] { return mvGetSceneInfo(self.get(), &i); }));  // the first call opens the file
  py::dict out;
  out["encoding"] = std::string(i.encoding);
  out["resolution"] = i.resolution;
  out["levels"] = i.levels;
  out["voxels"] = i.voxels;
  out["bytes"] = i.bytes;
  out["origin"] = triple(i.origin);
  out["voxel_size"] = i.voxelSize;
  out["lower"] = triple(i.lower);
  out["upper"] = triple(i.upper);
  return out;
}

py::dict scene_stats(const Scene& self) {
  MvSceneStats st{};
  st.byteSize = sizeof st;
  check(self.device(), nogil([&] { return mvGetSceneStats(self.get(), &st); }));
  py::dict out;
  out["paged"] = st.paged != 0;
  out["cache_bytes"] = st.cacheBytes;
  out["passes"] = st.passes;
  out["pages_streamed"] = st.pagesStreamed;
  out["peak_device_bytes"] = st.peakDeviceBytes;
  return out;
}

py::object trace(const Scene& self, const py::object& origins_obj, const py::object& directions_obj,
                 const py::object& tmax, const py::object& max_steps, bool colours) {
  const auto o = rows<float>(origins_obj, "origins", 3);
  const auto dir = rows<float>(directions_obj, "directions", 3);
  const size_t n = o.shape(0);
  if (size_t(dir.shape(0)) != n)
    bad_argument("directions: " + std::to_string(dir.shape(0)) + " rows for " + std::to_string(n) + " origins");
  std::vector<MvTraceRay> rays(n);
  const float* op = o.data();
  const float* dp = dir.data();
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) rays[i].org[k] = op[3 * i + k], rays[i].dir[k] = dp[3 * i + k];
  const float inf = std::numeric_limits<float>::infinity();
  if (tmax.is_none()) {
    for (auto& r : rays) r.tmax = inf;
  } else if (py::isinstance<py::array>(tmax)) {
    const auto t = rows<float>(tmax, "tmax", 0);
    if (size_t(t.shape(0)) != n)
      bad_argument("tmax: " + std::to_string(t.shape(0)) + " values for " + std::to_string(n) + " rays");
    for (size_t i = 0; i < n; ++i) rays[i].tmax = t.data()[i];
  } else {
    const auto t = static_cast<float>(number(tmax, "tmax"));
    for (auto& r : rays) r.tmax = t;
  }
  MvTraceArguments args;
  mvInitTraceArguments(&args);
  if (!max_steps.is_none()) {
    const py::object n = py::module_::import("operator").attr("index")(max_steps);
    if (n.attr("__lt__")(1).cast<bool>() || n.attr("__gt__")(py::int_(0xffffffffu)).cast<bool>())
      bad_argument("max_steps: " + py::str(n).cast<std::string>() + " is not from 1 to 2^32 - 1");
    args.maxSteps = n.cast<uint32_t>();
  }
  py::array hits(py::reinterpret_borrow<py::dtype>(py::module_::import("megavox._types").attr("HIT_DTYPE")),
                 std::vector<py::ssize_t>{py::ssize_t(n)});
  static_assert(sizeof(MvTraceHit) == 32);
  auto* h = static_cast<MvTraceHit*>(hits.mutable_data());
  std::optional<py::array_t<uint8_t>> rgba;
  if (colours) rgba.emplace(std::vector<py::ssize_t>{py::ssize_t(n), 4});
  uint8_t* c = colours ? rgba->mutable_data() : nullptr;
  MvError e;
  {
    py::gil_scoped_release nogil;
    e = colours ? mvTraceRaysRgba(self.get(), rays.data(), h, c, n, &args) : mvTraceRays(self.get(), rays.data(), h, n, &args);
  }
  check(self.device(), e);
  if (colours) return py::make_tuple(hits, *rgba);
  return hits;
}

py::dict camera_dict(const MvCamera& c) {
  py::dict out;
  out["eye"] = triple(c.eye);
  out["target"] = triple(c.target);
  out["up"] = triple(c.up);
  out["fov"] = c.fov;
  return out;
}

MvCamera camera_of(const py::dict& d) {
  MvCamera c{};
  auto vec = [&](const char* key, double* out, bool required, std::initializer_list<double> fallback) {
    if (!d.contains(key)) {
      if (required) bad_argument(std::string("camera: no '") + key + "' (a camera holds eye, target, up and fov)");
      std::copy(fallback.begin(), fallback.end(), out);
      return;
    }
    const py::sequence s = d[key].cast<py::sequence>();
    if (s.size() != 3) bad_argument(std::string("camera: '") + key + "' is not 3 numbers");
    for (int k = 0; k < 3; ++k) out[k] = number(s[k], key);
  };
  vec("eye", c.eye, true, {});
  vec("target", c.target, true, {});
  vec("up", c.up, false, {0, 1, 0});
  c.fov = d.contains("fov") ? number(d["fov"], "fov") : MV_DEFAULT_FOV;
  for (const auto& item : d) {
    const std::string k = item.first.cast<std::string>();
    if (k != "eye" && k != "target" && k != "up" && k != "fov")
      bad_argument("camera: unknown key '" + k + "' (a camera holds eye, target, up and fov)");
  }
  return c;
}

py::dict view_camera(const Scene& self, const std::string& view, const py::object& fov) {
  MvCamera c;
  const double degrees = fov.is_none() ? 0.0 : number(fov, "fov");
  check(self.device(), nogil([&] { return mvGetSceneViewCamera(self.get(), view.c_str(), degrees, &c); }));
  return camera_dict(c);
}

py::array_t<uint8_t> render(const Scene& self, uint32_t width, uint32_t height, const py::object& camera,
                            const std::string& view, const std::string& shading, double lod_pixels, uint32_t ao_samples) {
  if (width == 0 || height == 0) bad_argument("width and height: at least 1 pixel each");
  MvRenderArguments args;
  mvInitRenderArguments(&args);
  args.width = width;
  args.height = height;
  args.shading = shading.c_str();
  args.view = view.c_str();
  args.lodPixels = lod_pixels;
  args.aoSamples = ao_samples;
  std::optional<MvCamera> cam;
  if (!camera.is_none()) {
    if (!py::isinstance<py::dict>(camera)) bad_argument("camera: a dict with eye, target, up and fov is expected");
    cam = camera_of(camera.cast<py::dict>());
  }
  py::array_t<uint8_t> rgba({py::ssize_t(height), py::ssize_t(width), py::ssize_t(4)});
  uint8_t* out = rgba.mutable_data();
  MvError e;
  {
    py::gil_scoped_release nogil;
    e = mvRenderScene(self.get(), cam ? &*cam : nullptr, &args, out, 0);
  }
  check(self.device(), e);
  return rgba;
}

void save(const Scene& self, const py::object& path_obj) {
  const std::string path = fspath(path_obj);
  MvError e;
  {
    py::gil_scoped_release nogil;
    e = mvSaveScene(self.get(), path.c_str());
  }
  check(self.device(), e);
}

uint64_t colour_entries(const Scene& self) {
  uint64_t n = 0;
  check(self.device(), nogil([&] { return mvGetSceneColourEntries(self.get(), &n); }));
  return n;
}

}  // namespace

void bind_scenes(py::module_& m) {
  py::class_<Scene>(m, "Scene", "A voxel DAG on a device: ray queries and pictures. It keeps its device alive.")
      .def_property_readonly("device", &Scene::device_object)
      .def_property_readonly("info", &scene_info)
      .def_property_readonly("stats", &scene_stats)
      .def_property_readonly("colour_entries", &colour_entries)
      .def("save", &save, py::arg("path"))
      .def("trace", &trace, py::arg("origins"), py::arg("directions"), py::arg("tmax") = py::none(), py::kw_only(),
           py::arg("max_steps") = py::none(), py::arg("colours") = false)
      .def("view_camera", &view_camera, py::arg("view") = "iso", py::arg("fov") = py::none())
      .def("render", &render, py::arg("width"), py::arg("height"), py::kw_only(), py::arg("camera") = py::none(),
           py::arg("view") = "iso", py::arg("shading") = "shaded", py::arg("lod_pixels") = 1.0,
           py::arg("ao_samples") = 8);
  py::reinterpret_borrow<py::class_<Device>>(m.attr("Device"))
      .def("build", &build, py::arg("source"), py::kw_only(), py::arg("resolution") = 0, py::arg("format") = "svdag",
           py::arg("cube") = 0, py::arg("voxelize") = "conservative", py::arg("grid_origin") = "center",
           py::arg("grid") = py::none(), py::arg("output") = py::none(), py::arg("progress") = py::none())
      .def("open", &open_scene, py::arg("path"));
}

}  // namespace megavox_py
