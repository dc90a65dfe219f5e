// The extension module megavox._megavox; the package megavox (python/megavox) is its public face.
#include "binding.h"

namespace py = pybind11;

PYBIND11_MODULE(_megavox, m) {
  m.doc() = "megavox's compiled core: the C API bound for Python (use the package megavox).";
  m.attr("__version__") = mvGetVersionString();
  m.attr("IN_CORE") = py::int_(MV_CUBE_IN_CORE);
  megavox_py::bind_devices(m);
  megavox_py::bind_scenes(m);
  megavox_py::bind_points(m);
  megavox_py::bind_masks(m);
}
