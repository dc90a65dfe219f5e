// The CLI's names for the library's settings: a failure that names a setting (mv::Error::settings) is
// reported with the flag that sets it, since the library's message speaks its own terms.
#pragma once
#include <exception>
#include <string>

namespace mv::cli {

// The message of `e` with the flags of its settings after it: "... (raise --device-memory)",
// "... (--cube, --resolution)"; the message alone when it names none.
std::string message_with_flags(const std::exception& e);

}  // namespace mv::cli
