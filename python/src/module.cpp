// The extension module megavox._megavox; the package megavox (python/megavox) is its public face.
#include "binding.h"

namespace py = pybind11;

PYBIND11_MODULE(_megavox, m) {
  m.doc() = "megavox's compiled core: the C API bound for Python (use the package megavox).";
  m.attr("__version__") = mvGetVersionString();
  m.attr("IN_CORE") = py::int_(MV_CUBE_IN_CORE);
  // An argument pybind11 cannot convert is the caller's: megavox.InvalidArgumentError (a ValueError), not a
  // RuntimeError.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const py::cast_error& e) {
      py::object cls = py::module_::import("megavox._errors").attr("InvalidArgumentError");
      PyErr_SetObject(cls.ptr(), py::make_tuple(std::string("an argument of the wrong type: ") + e.what(),
                                                "MV_ERROR_INVALID_ARGUMENT").ptr());
    }
  });
  megavox_py::bind_devices(m);
  megavox_py::bind_scenes(m);
  megavox_py::bind_points(m);
  megavox_py::bind_masks(m);
}
