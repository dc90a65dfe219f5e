// megavox.points: point hierarchies built from a file or from arrays, and read back as arrays.
#include <array>
#include <memory>

#include "devices.h"

namespace megavox_py {

namespace {

// uint8 or uint16 values as uint16 (uint8 widened: a PLY's uchar colours are stored so).
py::array_t<uint16_t, py::array::c_style> widened(const py::handle& obj, const char* name, size_t columns) {
  if (py::isinstance<py::array>(obj) &&
      py::reinterpret_borrow<py::array>(obj).dtype().equal(py::dtype::of<uint8_t>())) {
    const auto narrow = rows<uint8_t>(obj, name, columns);
    return rows<uint16_t>(narrow.attr("astype")("uint16"), name, columns);
  }
  return rows<uint16_t>(obj, name, columns);
}

void check_count(py::ssize_t rows_given, size_t n, const char* name) {
  if (size_t(rows_given) != n)
    bad_argument(std::string(name) + ": " + std::to_string(rows_given) + " rows for " + std::to_string(n) + " points");
}

void build(const Device& device, const py::object& source, const py::object& out, const std::string& format,
           uint32_t depth, uint32_t max_node_points, const py::object& rgb, const py::object& intensity,
           const py::object& classification, const py::object& progress_fn, const std::string& tiles_version,
           const py::object& crs, const py::object& bounds) {
  const MvDevice d = device.get();
  const std::string output = fspath(out);
  Progress progress(progress_fn);
  MvPointBuildArguments args;
  mvInitPointBuildArguments(&args);
  args.format = format.c_str();
  args.tilesVersion = tiles_version.c_str();
  const std::string crs_text = crs.is_none() ? std::string() : crs.cast<std::string>();
  if (!crs.is_none()) args.crs = crs_text.c_str();
  std::array<double, 6> box{};
  if (!bounds.is_none()) {
    const py::sequence values = py::reinterpret_borrow<py::sequence>(bounds);
    if (!py::isinstance<py::sequence>(bounds) || py::len(values) != 6)
      throw py::value_error("bounds: six numbers, (min x, y, z, max x, y, z)");
    for (size_t k = 0; k < 6; ++k) box[k] = py::float_(values[k]).cast<double>();
    args.bounds = box.data();
  }
  args.depth = depth;
  args.maxNodePoints = max_node_points;
  args.progress = progress.function();
  args.progressUserPtr = progress.user();
  MvError e;
  if (py::isinstance<py::array>(source)) {
    MvPointArrays p;
    mvInitPointArrays(&p);
    const py::array a = py::reinterpret_borrow<py::array>(source);
    std::optional<py::array_t<float, py::array::c_style>> xyz32;
    std::optional<py::array_t<double, py::array::c_style>> xyz64;
    if (a.dtype().equal(py::dtype::of<double>())) {
      xyz64 = rows<double>(a, "xyz", 3);
      p.xyz64 = xyz64->data();
      p.count = xyz64->shape(0);
    } else {
      xyz32 = rows<float>(a, "xyz", 3);  // names any other dtype
      p.xyz32 = xyz32->data();
      p.count = xyz32->shape(0);
    }
    std::optional<py::array_t<uint16_t, py::array::c_style>> colours, values;
    std::optional<py::array_t<uint8_t, py::array::c_style>> classes;
    if (!rgb.is_none()) {
      colours = widened(rgb, "rgb", 3);
      check_count(colours->shape(0), p.count, "rgb");
      p.rgb = colours->data();
    }
    if (!intensity.is_none()) {
      values = widened(intensity, "intensity", 0);
      check_count(values->shape(0), p.count, "intensity");
      p.intensity = values->data();
    }
    if (!classification.is_none()) {
      classes = rows<uint8_t>(classification, "classification", 0);
      check_count(classes->shape(0), p.count, "classification");
      p.extra = classes->data();
      p.extraBytes = 1;
    }
    py::gil_scoped_release nogil;
    e = mvBuildPointsFromMemory(d, &p, output.c_str(), &args);
  } else {
    if (!rgb.is_none() || !intensity.is_none() || !classification.is_none())
      bad_argument("rgb, intensity, classification: only with a cloud given as arrays (a file carries its own)");
    const std::string input = fspath(source);
    py::gil_scoped_release nogil;
    e = mvBuildPointsFile(d, input.c_str(), output.c_str(), &args);
  }
  progress.check(d, e);
}

// The hierarchy at `path`, read whole: (info, nodes, xyz, rgb, intensity, extra, normal), columns it lacks as None.
py::tuple open_points(const Device& device, const py::object& path_obj) {
  const MvDevice d = device.get();
  const std::string path = fspath(path_obj);
  MvPoints p;
  {
    py::gil_scoped_release nogil;
    p = mvOpenPoints(d, path.c_str());
  }
  if (!p) check(d, failure_code(d));
  const std::unique_ptr<MvPointsTy, void (*)(MvPoints)> hold(p, mvReleasePoints);
  MvPointsInfo i;
  check(d, mvGetPointsInfo(p, &i));
  py::dict info;
  info["nodes"] = i.nodes;
  info["points"] = i.points;
  info["points_in"] = i.pointsIn;
  info["points_kept"] = i.pointsKept;
  info["points_dropped"] = i.pointsDropped;
  info["depth"] = i.depth;
  info["scale"] = py::make_tuple(i.scale[0], i.scale[1], i.scale[2]);
  info["offset"] = py::make_tuple(i.offset[0], i.offset[1], i.offset[2]);
  info["format"] = std::string(i.format);
  std::string crs(mvGetPointsCrs(p, nullptr, 0), '\0');
  if (!crs.empty()) mvGetPointsCrs(p, crs.data(), crs.size() + 1);
  info["crs"] = crs;
  std::vector<MvPointField> fields(mvGetPointFields(p, nullptr, 0));
  if (!fields.empty()) mvGetPointFields(p, fields.data(), fields.size());
  static const char* const kTypes[] = {"u1", "i1", "<u2", "<i2", "<u4", "<i4", "<u8", "<i8", "<f4", "<f8"};
  py::list field_list;
  for (const MvPointField& f : fields) {
    py::dict d;
    d["name"] = std::string(f.name);
    d["dtype"] = f.type < 10 ? kTypes[f.type] : "u1";
    d["offset"] = f.offset;
    d["count"] = f.count;
    d["scale"] = f.scale;
    d["add"] = f.add;
    field_list.append(d);
  }
  info["fields"] = field_list;
  py::array nodes(py::reinterpret_borrow<py::dtype>(py::module_::import("megavox._types").attr("NODE_DTYPE")),
                  std::vector<py::ssize_t>{py::ssize_t(i.nodes)});
  static_assert(sizeof(MvPointNode) == 40);
  const auto n = py::ssize_t(i.points);
  py::array_t<double> xyz({n, py::ssize_t(3)});
  py::object rgb = py::none(), intensity = py::none(), extra = py::none(), normal = py::none();
  float* normal_out = nullptr;
  if (i.attributes & MV_POINT_NORMAL) {
    py::array_t<float> a({n, py::ssize_t(3)});
    normal_out = a.mutable_data();
    normal = a;
  }
  uint16_t* rgb_out = nullptr;
  uint16_t* intensity_out = nullptr;
  uint8_t* extra_out = nullptr;
  if (i.attributes & MV_POINT_RGB) {
    py::array_t<uint16_t> a({n, py::ssize_t(3)});
    rgb_out = a.mutable_data();
    rgb = a;
  }
  if (i.attributes & MV_POINT_INTENSITY) {
    py::array_t<uint16_t> a({n});
    intensity_out = a.mutable_data();
    intensity = a;
  }
  if (i.attributes & MV_POINT_EXTRA) {
    py::array_t<uint8_t> a({n, py::ssize_t(i.extraBytes)});
    extra_out = a.mutable_data();
    extra = a;
  }
  auto* node_out = static_cast<MvPointNode*>(nodes.mutable_data());
  double* xyz_out = xyz.mutable_data();
  MvError e;
  {
    py::gil_scoped_release nogil;
    e = mvGetPointNodes(p, 0, i.nodes, node_out);
    if (e == MV_ERROR_NONE) e = mvGetPointData(p, 0, i.points, xyz_out, rgb_out, intensity_out, extra_out, normal_out);
  }
  check(d, e);
  return py::make_tuple(info, nodes, xyz, rgb, intensity, extra, normal);
}

}  // namespace

void bind_points(py::module_& m) {
  m.def("_points_build", &build, py::arg("device"), py::arg("source"), py::arg("out"), py::arg("format"),
        py::arg("depth"), py::arg("max_node_points"), py::arg("rgb"), py::arg("intensity"), py::arg("classification"),
        py::arg("progress"), py::arg("tiles_version"), py::arg("crs"), py::arg("bounds"));
  m.def("_points_open", &open_points, py::arg("device"), py::arg("path"));
}

}  // namespace megavox_py
