// What the service throws: a message for the client and its kind as the C API's code, the one table every
// front end reports failures by (the CLI's --json errors, the C API, the service's jobs).
#pragma once
#include <new>
#include <stdexcept>
#include <string>

#include "megavox/megavox.h"

namespace mv::serve {

class ServeError : public std::runtime_error {
 public:
  explicit ServeError(const std::string& message, MvError code = MV_ERROR_INVALID_ARGUMENT)
      : std::runtime_error(message), code(code) {}
  MvError code;
};

// The code of what a job or a request threw: a ServeError's own; the standard library's allocation failure:
// out of memory; anything else: unknown (a fault of the service's).
inline MvError code_of(const std::exception& e) noexcept {
  if (auto* s = dynamic_cast<const ServeError*>(&e)) return s->code;
  if (dynamic_cast<const std::bad_alloc*>(&e)) return MV_ERROR_OUT_OF_MEMORY;
  return MV_ERROR_UNKNOWN;
}

// The message to report: what(), or for the allocation failure, what it means.
inline std::string message_of(const std::exception& e) {
  return dynamic_cast<const std::bad_alloc*>(&e) ? "out of host memory" : e.what();
}

}  // namespace mv::serve
