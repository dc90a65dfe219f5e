// Every file or folder megavox writes is resolved and checked here before any work starts, so a mistyped -o
// fails in milliseconds and nothing a user owns is replaced by accident:
//   - an output that is one of the inputs (the same file, through links or hard links too) is refused;
//   - an existing target that is not a regular file (a FIFO, a device, a socket, a folder where a file is
//     meant) is refused, and so is any path under /dev or /proc;
//   - a symbolic link is written through: the file it names gets the new bytes and the link stays;
//   - the folder must exist and be writable (a missing folder, a path under a regular file are named);
//   - a name whose extension says another format than the one written is refused (x.mvx for OpenVDB bytes);
//   - with no_clobber, an existing file (or a non-empty folder) is refused;
//   - where the output's size can be estimated, the file system must have that much free.
// The writers themselves (atomic_file.h, atomic_dir.h) then write to an unnamed temporary file and give it the
// name only when every byte is out.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace mv::io {

enum class OutputKind {
  kFile,   // one file, replaced whole
  kFolder  // a folder of files (3D Tiles, a flight's frames), replaced whole (see atomic_dir.h)
};

struct OutputRequest {
  std::string path;                  // as the user gave it
  OutputKind kind = OutputKind::kFile;
  std::string format;                // what will be written, as format_of_extension names it; "" = no check
  std::vector<std::string> inputs;   // every file the work reads
  uint64_t estimated_bytes = 0;      // about what will be written; 0 = unknown (no free-space check)
  bool no_clobber = false;           // refuse an existing file, or a folder with anything in it

  OutputRequest(std::string path_, OutputKind kind_ = OutputKind::kFile, std::string format_ = "",
                std::vector<std::string> inputs_ = {}, uint64_t estimated_bytes_ = 0, bool no_clobber_ = false)
      : path(std::move(path_)), kind(kind_), format(std::move(format_)), inputs(std::move(inputs_)),
        estimated_bytes(estimated_bytes_), no_clobber(no_clobber_) {}
};

// Checks `r` as above and returns the path to write: `r.path` with a symbolic link in its last part followed
// to the file it names. Throws mv::Error naming the output and what is wrong.
std::string resolve_output(const OutputRequest& r);

// A folder that files are written into one by one (masks), made if missing: it must be a folder, or its
// nearest existing parent a writable folder. Throws mv::Error naming what is wrong; makes nothing.
void check_output_folder(const std::string& dir);

// The format a file name's extension says ("mvx", "png", "jpeg", "vdb", "nvdb", "symvox-svdag", "mvm", "3tz",
// ...), or "" when megavox knows no format by that extension.
std::string format_of_extension(const std::string& path);

// The process's file-creation mask (read without changing it).
unsigned current_umask();

}  // namespace mv::io
