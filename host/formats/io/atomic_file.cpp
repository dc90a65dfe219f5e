#include "atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <random>

#include "atomic_dir.h"
#include "file_ops.h"
#include "megavox/error.h"
#include "output_path.h"

namespace mv::io {

namespace {

// A free name beside `path` for a moment's use (the named fallback, or the step before a rename).
std::string spare_name(const std::string& path) {
  static thread_local std::mt19937_64 rng(std::random_device{}());
  const std::filesystem::path p(path);
  char suffix[24];
  std::snprintf(suffix, sizeof suffix, ".%012llx.tmp", (unsigned long long)(rng() & 0xffffffffffffull));
  return (p.parent_path() / ("." + p.filename().string() + suffix)).string();
}

// One output being written. The file is unnamed (O_TMPFILE) or, where the file system cannot, a hidden name.
class PendingFile {
 public:
  explicit PendingFile(const std::string& path) : path_(resolve_output({path})) {
    std::string folder = std::filesystem::path(path_).parent_path().string();
    if (folder.empty()) folder = ".";
    struct stat old {};
    const bool replacing = ::stat(path_.c_str(), &old) == 0;
    const mode_t mode = replacing ? (old.st_mode & 07777) : (0666 & ~current_umask());
    fd_ = ::open(folder.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0666);
    if (fd_ < 0) {
      if (errno != EOPNOTSUPP && errno != EISDIR && errno != EINVAL) fail(errno);
      for (int tries = 0; fd_ < 0 && tries < 100; ++tries) {
        named_ = spare_name(path_);
        fd_ = ::open(named_.c_str(), O_CREAT | O_EXCL | O_RDWR | O_CLOEXEC, 0600);
        if (fd_ < 0 && errno != EEXIST) fail(errno);
      }
      if (fd_ < 0) fail(EEXIST);
    }
    if (::fchmod(fd_, mode) != 0) fail(errno);  // the umask, or the replaced file's permissions
  }
  ~PendingFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!named_.empty()) ::unlink(named_.c_str());
  }
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;

  int fd() const { return fd_; }
  // A name that opens this file, for writers that want one.
  std::string name() const { return named_.empty() ? "/proc/self/fd/" + std::to_string(fd_) : named_; }
  const std::string& path() const { return path_; }

  // Syncs the bytes and puts the file at the target's name, replacing an older file in one step.
  void publish() {
    if (!in_folder_being_written(path_) && ::fsync(fd_) != 0) fail(errno);
    if (!named_.empty()) {
      if (rename_path(named_.c_str(), path_.c_str()) != 0) fail(errno, "cannot rename it into place");
      named_.clear();
      return;
    }
    if (link_open_file(fd_, path_.c_str()) == 0) return;
    if (errno != EEXIST) fail(errno, "cannot give it its name");
    // An older file is there: link beside it, then rename over it (rename replaces atomically, link cannot).
    std::string beside;
    int err = EEXIST;
    for (int tries = 0; err == EEXIST && tries < 100; ++tries) {
      beside = spare_name(path_);
      err = link_open_file(fd_, beside.c_str()) == 0 ? 0 : errno;
    }
    if (err) fail(err, "cannot give it its name");
    if (rename_path(beside.c_str(), path_.c_str()) != 0) {
      err = errno;
      ::unlink(beside.c_str());
      fail(err, "cannot rename it into place");
    }
  }

  [[noreturn]] void fail(int err, const std::string& what = "") const {
    throw IoError("cannot write '" + path_ + "'" + (what.empty() ? "" : " (" + what + ")") + ": " + std::strerror(err));
  }

 private:
  std::string path_, named_;
  int fd_ = -1;
};

}  // namespace

void write_atomically(const std::string& path, const std::function<bool(std::FILE*)>& write) {
  PendingFile out(path);
  const int fd = ::dup(out.fd());
  std::FILE* f = fd >= 0 ? ::fdopen(fd, "wb") : nullptr;
  if (!f) {
    const int err = errno;
    if (fd >= 0) ::close(fd);
    out.fail(err);
  }
  errno = 0;
  bool ok = write(f) && std::fflush(f) == 0;
  int err = errno;
  ok = std::fclose(f) == 0 && ok;
  if (!ok) out.fail(err ? err : errno ? errno : EIO);
  out.publish();
}

void write_atomically_by_name(const std::string& path, const std::function<void(const std::string& tmp)>& write) {
  PendingFile out(path);
  try {
    write(out.name());
  } catch (const std::exception& e) {
    throw CodedError(classify_or(e, ErrorCode::io), "cannot write '" + out.path() + "': " + e.what(), error_settings(e));
  }
  out.publish();
}

}  // namespace mv::io
