// Output files are written to PATH.tmp and renamed onto PATH only when every byte is out, so a failure
// never leaves a truncated or half-old file behind.
#pragma once
#include <cstdio>
#include <functional>
#include <string>

namespace mv::io {

// Opens PATH.tmp, calls `write` (false = failed, errno says why), flushes, closes and renames; on any
// failure removes PATH.tmp and throws mv::Error naming the file.
void write_atomically(const std::string& path, const std::function<bool(std::FILE*)>& write);

// For writers that want a file name: `write` writes PATH.tmp (throwing on failure), then it is renamed.
void write_atomically_by_name(const std::string& path, const std::function<void(const std::string& tmp)>& write);

}  // namespace mv::io
