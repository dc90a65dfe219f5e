// What the fuzz targets share. The readers take paths. The readers that open through io::open_read or
// io::MappedFile (PLY, LAS, .mvx, and assimp and OpenVDB through io::AssimpFiles and io::FileStreambuf) get
// each input as a memory file (io::memory_files: a path whose reads come from the input's bytes, no system
// calls); the others (SymVox, images, .mvm) get it written to one scratch file per process (under $TMPDIR, else
// /tmp; the same path for every input, removed at exit).
// An mv::Error is the expected outcome of bad input and is caught by the target; anything else -- another
// exception (std::terminate), a crash, an ASan or UBSan report, a leak, a broken promise of the reader's
// interface (MV_FUZZ_CHECK) -- stops the fuzzer and is a finding.
#pragma once
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "io/file_ops.h"

#define MV_FUZZ_CHECK(cond)                                                                      \
  do {                                                                                           \
    if (!(cond)) {                                                                               \
      std::fprintf(stderr, "MV_FUZZ_CHECK failed: %s (%s:%d)\n", #cond, __FILE__, __LINE__);    \
      std::abort();                                                                              \
    }                                                                                            \
  } while (0)

namespace mv::fuzz {

// This process's scratch path ending in `suffix` (".ply", ".obj", ...).
inline const std::string& input_path(const char* suffix) {
  static const std::string path = [&] {
    const char* dir = std::getenv("TMPDIR");
    std::string p = std::string(dir && *dir ? dir : "/tmp") + "/megavox-fuzz-" + std::to_string(::getpid()) + suffix;
    static std::string for_exit;
    for_exit = p;
    std::atexit([] { std::remove(for_exit.c_str()); });
    return p;
  }();
  return path;
}

// Writes the input to input_path(suffix) (truncating what the last input left) and returns that path.
inline const std::string& write_input(const uint8_t* data, size_t size, const char* suffix) {
  const std::string& path = input_path(suffix);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f || (size && std::fwrite(data, 1, size, f) != size) || std::fclose(f) != 0) {
    std::perror(path.c_str());  // the harness itself cannot run: not a finding of the reader
    std::exit(2);
  }
  return path;
}

// Puts the input as the memory file at input_path(suffix) (nothing is written) and returns that path. The
// bytes must outlive the reads: they are the caller's.
inline const std::string& memory_input(const uint8_t* data, size_t size, const char* suffix) {
  const std::string& path = input_path(suffix);
  io::memory_files::put(path, data, size);
  return path;
}

}  // namespace mv::fuzz
