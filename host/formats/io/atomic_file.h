// Output files are written to an unnamed temporary file in the target's folder (O_TMPFILE) and given the
// target's name only when every byte is out and on disk: a failure, or a run killed part-way, leaves neither a
// truncated file nor a temporary name behind. Where the file system has no unnamed files, a hidden named one
// beside the target stands in (a killed run can then leave it). New files get the user's umask; a replaced
// file keeps its permissions. The target is checked again (resolve_output) right before the work, so a
// FIFO, device or folder at the path is refused and a symbolic link is written through.
#pragma once
#include <cstdio>
#include <functional>
#include <string>

namespace mv::io {

// Calls `write` on the temporary file (false = failed, errno says why), then flushes, syncs (inside a folder
// written whole, the folder is synced once instead: atomic_dir.h) and names it PATH;
// on any failure nothing is left and mv::Error names PATH.
void write_atomically(const std::string& path, const std::function<bool(std::FILE*)>& write);

// For writers that open a file by name (OpenVDB): `write` writes the file `tmp` names (throwing on failure).
void write_atomically_by_name(const std::string& path, const std::function<void(const std::string& tmp)>& write);

}  // namespace mv::io
