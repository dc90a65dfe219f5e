#include "scratch_dir.h"

#include <stdlib.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "megavox/error.h"

namespace mv::bench {

ScratchDir::ScratchDir() {
  std::error_code ec;
  const std::filesystem::path tmp = std::filesystem::temp_directory_path(ec);
  std::string path = (ec ? std::filesystem::path("/tmp") : tmp).string() + "/megavox-bench-XXXXXX";
  if (!::mkdtemp(path.data()))
    throw Error("a scratch folder in " + path.substr(0, path.rfind('/')) + ": " + std::strerror(errno) +
                "; set TMPDIR to a writable directory");
  dir_ = path;
}

ScratchDir::~ScratchDir() {
  std::error_code ignored;
  std::filesystem::remove_all(dir_, ignored);
}

}  // namespace mv::bench
