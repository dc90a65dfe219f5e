#include "temp_file.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "file_ops.h"
#include "megavox/error.h"

namespace mv::io {

TempFile::TempFile(const std::string& purpose) : purpose_(purpose) {
  const char* dir = std::getenv("TMPDIR");
  dir_ = dir && *dir ? dir : "/tmp";
  std::string path = dir_ + "/megavox-XXXXXX";
  fd_ = ::mkstemp(path.data());
  if (fd_ < 0)
    throw IoError(purpose_ + " to " + dir_ + ": " + std::strerror(errno) + "; set TMPDIR to a writable directory");
  ::unlink(path.c_str());  // the file lives until it is closed
}

TempFile::~TempFile() {
  if (fd_ >= 0) ::close(fd_);
}

void TempFile::write_at(const void* data, uint64_t bytes, uint64_t offset) {
  const char* p = static_cast<const char*>(data);
  for (uint64_t done = 0; done < bytes;) {
    const ssize_t w = pwrite_some(fd_, p + done, bytes - done, static_cast<off_t>(offset + done));
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) throw IoError(purpose_ + " to " + dir_ + ": " + (w < 0 ? std::strerror(errno) : "disk full"));
    done += static_cast<uint64_t>(w);
  }
}

void TempFile::read_at(void* data, uint64_t bytes, uint64_t offset) const {
  char* p = static_cast<char*>(data);
  for (uint64_t done = 0; done < bytes;) {
    const ssize_t r = pread_some(fd_, p + done, bytes - done, static_cast<off_t>(offset + done));
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) throw IoError(purpose_ + ": reading back from " + dir_ + ": " + (r < 0 ? std::strerror(errno) : "short read"));
    done += static_cast<uint64_t>(r);
  }
}

void* TempFile::map(uint64_t bytes) {
  if (::ftruncate(fd_, static_cast<off_t>(bytes)) != 0)
    throw IoError(purpose_ + " to " + dir_ + ": " + std::strerror(errno));
  void* p = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, 0);
  if (p == MAP_FAILED) throw IoError(purpose_ + ": mapping " + std::to_string(bytes) + " bytes: " + std::strerror(errno));
  return p;
}

void TempFile::unmap(void* p, uint64_t bytes) {
  if (p) ::munmap(p, bytes);
}

}  // namespace mv::io
