// megavox — the one exception type thrown across module boundaries, and the one table that sorts failures into
// the codes every front end reports (the C API's MvError, the CLI's --json errors, the service's job errors).
#pragma once
#include <cstdint>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>

namespace mv {

// The settings of the library a failure is about, so that each front end can name them as its users know them
// (the CLI's flags, the C API's fields, the service's keys) while the message itself speaks the library's
// terms ("the resolution", "the device memory budget"). Bits: one failure may concern several.
enum Setting : uint32_t {
  setting_none = 0,
  setting_resolution = 1u << 0,     // "the resolution"
  setting_cube = 1u << 1,           // "the cube size" (out-of-core builds)
  setting_encoding = 1u << 2,       // "the encoding" (svo, svdag, ...) or a point cloud's "output format"
  setting_voxelize = 1u << 3,       // "the voxelization rule"
  setting_grid_origin = 1u << 4,    // "the grid origin"
  setting_bounds = 1u << 5,         // "the bounds"
  setting_host_memory = 1u << 6,    // "the host memory budget"
  setting_device_memory = 1u << 7,  // "the device memory budget"
  setting_lod_pixels = 1u << 8,     // "the level-of-detail pixel size"
  setting_ao_radius = 1u << 9,      // "the ambient-occlusion radius"
  setting_cache_memory = 1u << 10,  // "the page cache budget"
  setting_width = 1u << 11,         // "the picture width"
  setting_depth = 1u << 12,         // "the depth" (point hierarchies)
  setting_max_node_points = 1u << 13,  // "the node point limit"
  setting_no_clobber = 1u << 14,    // "replacing outputs was refused"
  setting_frames = 1u << 15,        // "the frame count" (pictures during a point build)
  setting_eye = 1u << 16,           // "the eye" (a camera's position)
  setting_target = 1u << 17,        // "the target" (where a camera looks)
  setting_up = 1u << 18,            // "the up direction"
  setting_fov = 1u << 19,           // "the field of view"
  setting_view = 1u << 20,          // "the preset view" (front, iso, ...)
};
inline Setting operator|(Setting a, Setting b) { return static_cast<Setting>(uint32_t(a) | uint32_t(b)); }

// Carries a complete, user-facing message ("what went wrong, with what, and what is left").
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message, Setting settings = setting_none)
      : std::runtime_error(message), settings(settings) {}
  Setting settings;  // what a front end may name beside the message
};

// The device memory budget (or the largest single allocation) cannot hold a buffer: a smaller problem
// (smaller out-of-core cubes) may still fit.
class DeviceMemoryError : public Error {
 public:
  explicit DeviceMemoryError(const std::string& message, Setting settings = setting_device_memory)
      : Error(message, settings) {}
};

// A file or folder cannot be opened, read, written, renamed or synced: the operating system refused or failed,
// whatever the bytes hold (a malformed file is a plain Error).
class IoError : public Error {
 public:
  using Error::Error;
};

// The compute device or its driver failed a call the library made correctly (a lost device, a kernel the
// driver cannot build).
class DeviceError : public Error {
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
  input = 7,               // the input is malformed or not what the call takes
  io = 8,                  // a file cannot be opened, read or written
  device = 9,              // the device or its driver failed
};

// An error whose kind its thrower knows better than its type says (a bad option, a missing device).
class CodedError : public Error {
 public:
  CodedError(ErrorCode code, const std::string& message, Setting settings = setting_none)
      : Error(message, settings), code(code) {}
  ErrorCode code;
};

// The code of an exception: a CodedError's own; device or host memory: out_of_memory; a file the system
// refused: io; a device failure: device; any other mv::Error (malformed input): input; anything else: unknown.
inline ErrorCode classify(const std::exception& e) noexcept {
  if (auto* c = dynamic_cast<const CodedError*>(&e)) return c->code;
  if (dynamic_cast<const DeviceMemoryError*>(&e) || dynamic_cast<const std::bad_alloc*>(&e))
    return ErrorCode::out_of_memory;
  if (dynamic_cast<const IoError*>(&e)) return ErrorCode::io;
  if (dynamic_cast<const DeviceError*>(&e)) return ErrorCode::device;
  if (dynamic_cast<const Error*>(&e)) return ErrorCode::input;
  return ErrorCode::unknown;
}

// The settings an exception names (setting_none for one that is no mv::Error).
inline Setting error_settings(const std::exception& e) noexcept {
  auto* m = dynamic_cast<const Error*>(&e);
  return m ? m->settings : setting_none;
}

// classify(e), or `otherwise` where that is unknown: a wrapper that adds where a failure happened keeps what it
// was, and names what a foreign exception most likely means there (a write's: io).
inline ErrorCode classify_or(const std::exception& e, ErrorCode otherwise) noexcept {
  const ErrorCode c = classify(e);
  return c == ErrorCode::unknown ? otherwise : c;
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
    case ErrorCode::io: return "MV_ERROR_IO";
    case ErrorCode::device: return "MV_ERROR_DEVICE";
  }
  return "MV_ERROR_(not a code)";
}

}  // namespace mv
