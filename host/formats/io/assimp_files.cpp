#include "io/assimp_files.h"

#include <assimp/IOStream.hpp>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#include "io/file_ops.h"
#include "megavox/error.h"

namespace mv::io {

namespace {

class FileStream final : public Assimp::IOStream {
 public:
  FileStream(FilePtr file, std::string path, std::string& error)
      : file_(std::move(file)), path_(std::move(path)), error_(error) {
    // the size of a regular file or a memory file; a stream without one (a pipe) reports 0
    if (std::fseek(file_.get(), 0, SEEK_END) == 0) {
      const long end = std::ftell(file_.get());
      size_ = end > 0 ? static_cast<size_t>(end) : 0;
    }
    std::fseek(file_.get(), 0, SEEK_SET);
  }
  size_t Read(void* buffer, size_t size, size_t count) override {
    if (size == 0 || count == 0) return 0;
    if (count > SIZE_MAX / size) count = SIZE_MAX / size;
    try {
      const size_t got = read_some(file_.get(), buffer, size * count, path_);
      at_ += got;
      // The reads end before the size the file had when opened: it was cut while read. assimp would take the
      // part as the whole file.
      if (got < size * count && at_ < size_ && error_.empty())
        error_ = path_ + ": the file ended at byte " + std::to_string(at_) + " of its " + std::to_string(size_) +
                 " (truncated while read?)";
      return got / size;
    } catch (const Error& e) {
      if (error_.empty()) error_ = e.what();
      return 0;
    }
  }
  size_t Write(const void*, size_t, size_t) override { return 0; }
  aiReturn Seek(size_t offset, aiOrigin origin) override {
    const int whence = origin == aiOrigin_CUR ? SEEK_CUR : origin == aiOrigin_END ? SEEK_END : SEEK_SET;
    // a backward move from the current position comes as a wrapped size_t, as for assimp's own stream
    const long by = static_cast<long>(offset);
    if (std::fseek(file_.get(), by, whence) != 0) return aiReturn_FAILURE;
    const long from = whence == SEEK_SET ? 0 : static_cast<long>(whence == SEEK_CUR ? at_ : size_);
    at_ = static_cast<size_t>(from + by);
    return aiReturn_SUCCESS;
  }
  size_t Tell() const override { return at_; }
  size_t FileSize() const override { return size_; }
  void Flush() override {}

 private:
  FilePtr file_;
  std::string path_;
  std::string& error_;
  size_t size_ = 0;
  size_t at_ = 0;  // the position: Read and Seek keep it (ftell may cost a system call)
};

}  // namespace

bool AssimpFiles::Exists(const char* path) const {
  try {
    open_read(path);
    return true;
  } catch (const Error&) {
    return false;
  }
}

Assimp::IOStream* AssimpFiles::Open(const char* path, const char* mode) {
  if (!mode || std::strchr(mode, 'w') || std::strchr(mode, 'a') || std::strchr(mode, '+')) return nullptr;
  try {
    return new FileStream(open_read(path), path, error_);
  } catch (const Error&) {
    return nullptr;  // assimp reports the file it could not open
  }
}

void AssimpFiles::Close(Assimp::IOStream* stream) { delete stream; }

}  // namespace mv::io
