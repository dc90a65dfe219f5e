#include "binding.h"

#include <cstdint>

namespace megavox_py {

void raise(MvError code, const std::string& message) {
  py::object exc = py::module_::import("megavox._errors").attr("error_class")(mvGetErrorString(code));
  // A message may quote bytes of a file that are not UTF-8: those become U+FFFD, never a decoding error.
  py::object text = py::reinterpret_steal<py::object>(
      PyUnicode_DecodeUTF8(message.data(), static_cast<Py_ssize_t>(message.size()), "replace"));
  if (!text) throw py::error_already_set();
  PyErr_SetObject(exc.ptr(), py::make_tuple(text, mvGetErrorString(code)).ptr());
  throw py::error_already_set();
}

namespace {

// The last error of a call on this thread. A device's record is shared by every thread that calls it, so the
// binding reads the error its error function saw on the failing thread, not the record another thread may
// have overwritten since.
struct ThreadError {
  MvError code = MV_ERROR_NONE;
  std::string message;
};
thread_local ThreadError t_error;

void on_error(void*, MvError code, const char* message) {
  t_error.code = code;
  t_error.message = message;
}

}  // namespace

void watch_errors(MvDevice device) { mvSetDeviceErrorFunction(device, &on_error, nullptr); }

void check(MvDevice device, MvError code) {
  if (code == MV_ERROR_NONE) return;
  std::string message;
  if (device && t_error.code != MV_ERROR_NONE) {
    message = std::move(t_error.message);
  } else {
    message = mvGetDeviceLastErrorMessage(device);  // NULL: the C API's own per-thread record
    mvGetDeviceError(device);
  }
  t_error = {};
  raise(code, message);
}

MvError failure_code(MvDevice device) {
  if (device && t_error.code != MV_ERROR_NONE) return t_error.code;
  const MvError code = mvGetDeviceError(device);
  return code == MV_ERROR_NONE ? MV_ERROR_UNKNOWN : code;
}

void bad_argument(const std::string& message) { raise(MV_ERROR_INVALID_ARGUMENT, message); }

bool Progress::call(void* user, const char* stage, double fraction) {
  auto* self = static_cast<Progress*>(user);
  py::gil_scoped_acquire gil;
  if (self->failure_) return false;
  try {
    py::object answer = self->callable_(stage, fraction);
    if (answer.is_none()) return true;
    const int yes = PyObject_IsTrue(answer.ptr());  // -1: the answer has no truth value (an error is set)
    if (yes < 0) throw py::error_already_set();
    return yes != 0;
  } catch (py::error_already_set& e) {
    self->failure_.emplace(std::move(e));
    return false;
  }
}

void Progress::check(MvDevice device, MvError code) {
  if (failure_) {
    mvGetDeviceError(device);  // the C API's "cancelled" record, replaced by what the callable raised
    t_error = {};
    py::error_already_set e = std::move(*failure_);
    failure_.reset();
    throw e;
  }
  megavox_py::check(device, code);
}

std::string fspath(const py::handle& path) {
  // The file system's bytes (os.fsencode), so any name that exists opens, UTF-8 or not.
  const py::bytes b = py::module_::import("os").attr("fsencode")(path);
  return std::string(b);
}

std::string dtype_name(const py::array& a) { return py::str(a.dtype()).cast<std::string>(); }

template <class T>
py::array_t<T, py::array::c_style> contiguous(const py::handle& a) {
  // numpy.require copies an array that is not C-contiguous or not aligned (both lossless); it raises on failure.
  py::object out = py::module_::import("numpy").attr("require")(a, py::dtype::of<T>(), py::make_tuple("C", "A"));
  return py::reinterpret_borrow<py::array_t<T, py::array::c_style>>(out);
}

template <class T>
py::array_t<T, py::array::c_style> rows(const py::handle& obj, const char* name, size_t columns) {
  if (!py::isinstance<py::array>(obj))
    bad_argument(std::string(name) + ": a numpy array is expected, not " + py::str(py::type::of(obj)).cast<std::string>());
  const py::array a = py::reinterpret_borrow<py::array>(obj);
  if (!a.dtype().equal(py::dtype::of<T>()))
    bad_argument(std::string(name) + ": dtype " + dtype_name(a) + " where " +
                 py::str(py::dtype::of<T>()).cast<std::string>() + " is expected");
  const size_t want_ndim = columns ? 2 : 1;
  if (size_t(a.ndim()) != want_ndim || (columns && size_t(a.shape(1)) != columns)) {
    std::string shape = "(";
    for (py::ssize_t d = 0; d < a.ndim(); ++d) shape += (d ? ", " : "") + std::to_string(a.shape(d));
    shape += a.ndim() == 1 ? ",)" : ")";
    bad_argument(std::string(name) + ": shape " + shape + " where " +
                 (columns ? "(n, " + std::to_string(columns) + ")" : std::string("(n,)")) + " is expected");
  }
  return contiguous<T>(a);
}

template py::array_t<uint8_t, py::array::c_style> contiguous<uint8_t>(const py::handle&);
template py::array_t<uint16_t, py::array::c_style> contiguous<uint16_t>(const py::handle&);
template py::array_t<float, py::array::c_style> rows<float>(const py::handle&, const char*, size_t);
template py::array_t<double, py::array::c_style> rows<double>(const py::handle&, const char*, size_t);
template py::array_t<uint8_t, py::array::c_style> rows<uint8_t>(const py::handle&, const char*, size_t);
template py::array_t<uint16_t, py::array::c_style> rows<uint16_t>(const py::handle&, const char*, size_t);
template py::array_t<uint32_t, py::array::c_style> rows<uint32_t>(const py::handle&, const char*, size_t);

}  // namespace megavox_py
