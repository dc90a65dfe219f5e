// megavox — the one exception type thrown across module boundaries, and the one table that sorts failures into
// the codes every front end reports (the C API's MvError, the CLI's --json errors, the service's job errors).
#pragma once
#include <exception>
#include <new>
#include <stdexcept>
#include <string>

namespace mv {

// Carries a complete, user-facing message ("what went wrong, with what, and what is left").
// The CLI prints what() on one line and exits non-zero.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

// The device memory budget (or the largest single allocation) cannot hold a buffer: a smaller problem
// (smaller out-of-core cubes) may still fit.
class DeviceMemoryError : public Error {
 public:
  using Error::Error;
};

// What kind of failure an error is. The values equal the C API's MvError (include/megavox/megavox.h), so a code
// converts to it by a cast.
enum class ErrorCode : int {
  none = 0,
  unknown = 1,             // an unexpected failure inside megavox
  invalid_argument = 2,    // a bad option, a malformed value, an unknown name
  invalid_operation = 3,   // the call does not apply to this object now
  out_of_memory = 4,       // the device or host memory budget cannot hold the work
  unsupported_device = 5,  // no device matches the selector
  cancelled = 6,           // the user or a progress function stopped the work
  input = 7,               // the input cannot be read, is malformed, or the output cannot be written
};

// An error whose kind its thrower knows better than its type says (a bad option, a missing device).
class CodedError : public Error {
 public:
  CodedError(ErrorCode code, const std::string& message) : Error(message), code(code) {}
  ErrorCode code;
};

// The code of an exception: a CodedError's own; device or host memory: out_of_memory; any other mv::Error (a
// file that cannot be read or written, or is malformed): input; anything else: unknown.
inline ErrorCode classify(const std::exception& e) noexcept {
  if (auto* c = dynamic_cast<const CodedError*>(&e)) return c->code;
  if (dynamic_cast<const DeviceMemoryError*>(&e) || dynamic_cast<const std::bad_alloc*>(&e))
    return ErrorCode::out_of_memory;
  if (dynamic_cast<const Error*>(&e)) return ErrorCode::input;
  return ErrorCode::unknown;
}

// The message to report: what(), or for the standard library's allocation failure, what it means.
inline std::string error_message(const std::exception& e) {
  return dynamic_cast<const std::bad_alloc*>(&e) ? "out of host memory" : e.what();
}

// "MV_ERROR_INPUT", ...: the C API's name of a code.
inline const char* error_code_name(ErrorCode code) noexcept {
  switch (code) {
    case ErrorCode::none: return "MV_ERROR_NONE";
    case ErrorCode::unknown: return "MV_ERROR_UNKNOWN";
    case ErrorCode::invalid_argument: return "MV_ERROR_INVALID_ARGUMENT";
    case ErrorCode::invalid_operation: return "MV_ERROR_INVALID_OPERATION";
    case ErrorCode::out_of_memory: return "MV_ERROR_OUT_OF_MEMORY";
    case ErrorCode::unsupported_device: return "MV_ERROR_UNSUPPORTED_DEVICE";
    case ErrorCode::cancelled: return "MV_ERROR_CANCELLED";
    case ErrorCode::input: return "MV_ERROR_INPUT";
  }
  return "MV_ERROR_(not a code)";
}

}  // namespace mv
