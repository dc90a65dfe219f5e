#include "atomic_file.h"

#include <cerrno>
#include <cstring>

#include "file_ops.h"
#include "megavox/error.h"

namespace mv::io {

void write_atomically(const std::string& path, const std::function<bool(std::FILE*)>& write) {
  const std::string tmp = path + ".tmp";
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) throw Error("cannot write '" + tmp + "': " + std::strerror(errno));
  errno = 0;
  bool ok = write(f) && std::fflush(f) == 0;
  int err = errno;
  ok = std::fclose(f) == 0 && ok;
  if (!ok) {
    if (!err) err = errno ? errno : EIO;
    std::remove(tmp.c_str());
    throw Error("cannot write '" + tmp + "': " + std::strerror(err));
  }
  write_atomically_by_name(path, [](const std::string&) {});
}

void write_atomically_by_name(const std::string& path, const std::function<void(const std::string& tmp)>& write) {
  const std::string tmp = path + ".tmp";
  try {
    write(tmp);
  } catch (const std::exception& e) {
    std::remove(tmp.c_str());
    throw Error("cannot write '" + tmp + "': " + e.what());
  }
  if (rename_path(tmp.c_str(), path.c_str()) != 0) {
    int err = errno;
    std::remove(tmp.c_str());
    throw Error("cannot rename '" + tmp + "' to '" + path + "': " + std::strerror(err));
  }
}

}  // namespace mv::io
