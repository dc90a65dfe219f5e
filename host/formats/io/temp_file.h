// Scratch files for data that does not fit the host memory budget: created in $TMPDIR (or /tmp) and unlinked
// at once, so they vanish when closed, even after a crash.
#pragma once
#include <cstdint>
#include <string>

namespace mv::io {

// An open, already unlinked temporary file; closed on destruction.
class TempFile {
 public:
  // `purpose` names the data in error messages ("spilling triangles").
  explicit TempFile(const std::string& purpose);
  ~TempFile();
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;

  int fd() const { return fd_; }
  void write_at(const void* data, uint64_t bytes, uint64_t offset);  // all of it, or mv::Error
  void read_at(void* data, uint64_t bytes, uint64_t offset) const;   // all of it, or mv::Error
  // Maps the first `bytes` (grown to that size) read-write, shared: the kernel pages it to the file under
  // memory pressure. Throws mv::Error on failure. Unmap with unmap().
  void* map(uint64_t bytes);
  float* map_floats(uint64_t bytes) { return static_cast<float*>(map(bytes)); }
  static void unmap(void* p, uint64_t bytes);

 private:
  std::string purpose_, dir_;
  int fd_ = -1;
};

}  // namespace mv::io
