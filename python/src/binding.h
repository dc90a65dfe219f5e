// What every part of the Python binding shares: C API errors as Python exceptions, the progress bridge, and
// numpy arrays checked against what a call takes. The binding sits on the public C API alone.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <optional>
#include <string>

#include "megavox/megavox.h"

namespace megavox_py {

namespace py = pybind11;

// Runs `f` (a C API call) with the GIL released: every call that may wait for a device does, since a build
// on another thread holds the device while its progress callback waits for the GIL.
template <class F>
auto nogil(F&& f) {
  py::gil_scoped_release release;
  return f();
}

// Raises the Python exception of `code` (megavox._errors maps each MvError to a class) with `message`.
[[noreturn]] void raise(MvError code, const std::string& message);
// Raises the error a call on `device` just recorded on this thread (NULL: the C API's per-thread record), when
// `code` is not MV_ERROR_NONE.
void check(MvDevice device, MvError code);
// Sends the errors of calls on `device` to a per-thread record that check() and failure_code() read (every
// Device of the module is watched so).
void watch_errors(MvDevice device);
// The code of the error `device` recorded (clearing it; its message stays), for a call that returned NULL.
MvError failure_code(MvDevice device);
// Raises megavox.InvalidArgumentError (a ValueError) with `message`.
[[noreturn]] void bad_argument(const std::string& message);

// A Python callable as an MvProgressMonitorFunction. It runs with the GIL; a False return cancels; an
// exception it raises cancels too and is kept, to be raised again in place of the C API's "cancelled".
class Progress {
 public:
  explicit Progress(py::object callable) : callable_(std::move(callable)) {}
  MvProgressMonitorFunction function() const { return callable_.is_none() ? nullptr : &Progress::call; }
  void* user() { return this; }
  // After the C call (GIL held): raises what the callable raised, else the call's own error.
  void check(MvDevice device, MvError code);

 private:
  static bool call(void* user, const char* stage, double fraction);
  py::object callable_;
  std::optional<py::error_already_set> failure_;
};

// `obj` as a C-contiguous array of dtype T, shape (n, columns) (columns 0: shape (n,)); `name` names the
// argument in the error. Only dtype T is taken (a layout that is not C-contiguous is copied, which loses
// nothing); anything else raises InvalidArgumentError.
template <class T>
py::array_t<T, py::array::c_style> rows(const py::handle& obj, const char* name, size_t columns);

// A path argument (str, bytes or os.PathLike) as the C API takes it.
std::string fspath(const py::handle& path);

// `a` (of dtype T already) as a C-contiguous, aligned array: itself, or a copy.
template <class T>
py::array_t<T, py::array::c_style> contiguous(const py::handle& a);

// The dtype's name as numpy says it ("float64").
std::string dtype_name(const py::array& a);

// Parts of the module, each binding one family.
void bind_devices(py::module_& m);
void bind_scenes(py::module_& m);
void bind_points(py::module_& m);
void bind_masks(py::module_& m);

}  // namespace megavox_py
