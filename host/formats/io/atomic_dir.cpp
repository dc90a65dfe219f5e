#include "atomic_dir.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "file_ops.h"
#include "megavox/error.h"
#include "output_path.h"

namespace mv::io {

namespace fs = std::filesystem;

namespace {

// Whether `dir` may be replaced: absent, an empty folder, or a folder holding `marker`.
void check_replaceable(const fs::path& dir, const std::string& marker) {
  std::error_code ec;
  const fs::file_status st = fs::symlink_status(dir, ec);
  if (!fs::exists(st)) return;
  if (!fs::is_directory(st))
    throw IoError("cannot write '" + dir.string() + "': it exists and is not a folder; remove it or choose another name");
  if (fs::is_empty(dir, ec) || fs::exists(dir / marker, ec)) return;
  throw IoError("cannot write '" + dir.string() + "': it is a folder with other files in it (no " + marker +
              "), not replacing it; remove it or choose another name");
}

// Puts `tmp` in `dir`'s place; an old `dir` is swapped out atomically where the file system can, else moved
// aside first. The old folder is removed afterwards.
void swap_in(const fs::path& tmp, const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(dir, ec))) {
    if (rename_path(tmp.c_str(), dir.c_str()) != 0)
      throw IoError("cannot rename '" + tmp.string() + "' to '" + dir.string() + "': " + std::strerror(errno));
    return;
  }
  if (exchange_paths(tmp.c_str(), dir.c_str()) == 0) {
    fs::remove_all(tmp, ec);  // now the old folder; a leftover is harmless
    return;
  }
  const fs::path old = tmp.string() + ".old";
  if (rename_path(dir.c_str(), old.c_str()) != 0)
    throw IoError("cannot move the old '" + dir.string() + "' aside: " + std::strerror(errno));
  if (rename_path(tmp.c_str(), dir.c_str()) != 0) {
    const int err = errno;
    rename_path(old.c_str(), dir.c_str());  // put the old one back
    throw IoError("cannot rename '" + tmp.string() + "' to '" + dir.string() + "': " + std::strerror(err));
  }
  fs::remove_all(old, ec);
}

// The temporary folder this thread's write_dir_atomically is filling (empty when none).
thread_local std::string t_folder;

// Every file of the file system holding `dir` on disk (syncfs: one call for the whole folder).
void sync_folder(const std::string& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  const bool ok = fd >= 0 && ::syncfs(fd) == 0;
  const int err = errno;
  if (fd >= 0) ::close(fd);
  if (!ok) throw IoError("cannot sync '" + dir + "' to disk: " + std::strerror(err));
}

}  // namespace

bool in_folder_being_written(const std::string& path) {
  return !t_folder.empty() && path.size() > t_folder.size() && path.compare(0, t_folder.size(), t_folder) == 0 &&
         path[t_folder.size()] == '/';
}

void write_dir_atomically(const std::string& dir, const std::string& marker,
                          const std::function<void(const std::string& tmp_dir)>& write) {
  fs::path target = fs::path(dir).lexically_normal();
  if (target.has_filename() == false) target = target.parent_path();  // "out/" -> "out"
  if (target.empty() || target == "." || target == "..")
    throw IoError("cannot write into '" + dir + "': name a new or earlier output folder, not the current one");
  check_replaceable(target, marker);

  std::string tmp = target.string() + ".tmp-XXXXXX";
  if (!::mkdtemp(tmp.data()))
    throw IoError("cannot create a temporary folder beside '" + target.string() + "': " + std::strerror(errno));
  // mkdtemp makes it private (0700); the output is for others to serve too, as the user's umask says.
  if (::chmod(tmp.c_str(), 0777 & ~current_umask()) != 0) {
    const int err = errno;
    ::rmdir(tmp.c_str());
    throw IoError("cannot set the permissions of '" + tmp + "': " + std::strerror(err));
  }
  try {
    t_folder = tmp;
    write(tmp);
    t_folder.clear();
    sync_folder(tmp);
    swap_in(tmp, target);
  } catch (const std::exception& e) {
    t_folder.clear();
    std::error_code ec;
    fs::remove_all(tmp, ec);
    throw CodedError(classify_or(e, ErrorCode::io), "cannot write '" + target.string() + "' (nothing was changed): " + e.what(),
                     error_settings(e));
  }
}

}  // namespace mv::io
