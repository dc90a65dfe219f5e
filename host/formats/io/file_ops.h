// The one door of megavox's own file code to the file system: every read, write and rename of a reader or
// writer goes through here, so tests can make one of them fail (io::faults below) without root-only tricks.
// In normal runs these are the plain stdio / POSIX calls. assimp and OpenVDB read through here too
// (io/assimp_files.h, io/file_streambuf.h); the files OpenVDB writes itself still go through our rename.
#pragma once
#include <sys/types.h>

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

namespace mv::io {

using FilePtr = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

// `path` opened for reading: fopen(path, "rb"), or a stream over a memory file's bytes (below). mv::Error
// "cannot open 'PATH': ..." when it cannot be opened.
FilePtr open_read(const std::string& path);
// `path` opened for reading, unbuffered (the readers' reads are large), with its size in *size: the size bounds
// every count a header declares, so a pipe or a directory, which have none, are refused. mv::Error naming
// what is wrong.
FilePtr open_regular(const std::string& path, uint64_t* size);

// A whole file, read-only: mapped (mmap), or a memory file's bytes in place. mv::Error when it cannot be
// opened or mapped. Reads from a mapping go through copy_mapped (the file may shrink while mapped).
class MappedFile {
 public:
  MappedFile() = default;
  explicit MappedFile(const std::string& path);
  MappedFile(MappedFile&& other) noexcept;
  MappedFile& operator=(MappedFile&& other) noexcept;
  ~MappedFile();
  const unsigned char* data() const { return data_; }
  uint64_t size() const { return size_; }

 private:
  const unsigned char* data_ = nullptr;
  uint64_t size_ = 0;
  bool mapped_ = false;  // false: a memory file's bytes, not ours to unmap
};

// A test seam for the fuzz targets: while a path is put here, open_read, open_regular, first_bytes,
// read_whole_file and MappedFile read `bytes` (owned by the caller) for it instead of the file system, so a
// fuzz input costs no system calls. One path at a time; put and clear must not race with the readers.
namespace memory_files {
void put(const std::string& path, const void* bytes, size_t size);
void clear();
}  // namespace memory_files

// Up to `bytes` from `f`: fewer only at the end of the file. A read error throws mv::Error
// "PATH: read error: ...".
size_t read_some(std::FILE* f, void* data, size_t bytes, const std::string& path);
// Exactly `n` bytes of `f` from byte `at`: mv::Error "PATH: cannot seek to byte AT: ..." or "PATH: the file
// ended early, at byte AT", read errors as read_some's.
std::vector<uint8_t> read_at(std::FILE* f, uint64_t at, uint64_t n, const std::string& path);
// The first `n` bytes of a file (fewer when it is shorter), to tell its format; mv::Error when it cannot be
// opened or read.
std::string first_bytes(const std::string& path, size_t n);
// All of a file's bytes (a regular file or not), read errors as read_some's.
std::vector<char> read_whole_file(const std::string& path);
// All `bytes` to `f`, or false with errno set.
bool write_all(std::FILE* f, const void* data, size_t bytes);
// pread / pwrite of a file descriptor: as the POSIX calls (-1 and errno on failure).
ssize_t pread_some(int fd, void* data, size_t bytes, off_t offset);
ssize_t pwrite_some(int fd, const void* data, size_t bytes, off_t offset);
// A copy out of a memory-mapped file (a page of MvxPages): true, or false with errno set: EFAULT when the
// range lies past the file's end (the file shrank after it was mapped: SIGBUS, caught), EIO when injected.
bool copy_mapped(void* out, const void* mapped, size_t bytes);
// rename(2) and renameat2(2) with RENAME_EXCHANGE: 0, or -1 and errno.
int rename_path(const char* from, const char* to);
int exchange_paths(const char* a, const char* b);
// Gives the open, unnamed file `fd` (O_TMPFILE) the name `to` (linkat(2)): 0, or -1 and errno (EEXIST when
// `to` exists). Counted as a rename by the fault injection below.
int link_open_file(int fd, const char* to);

// Fault injection for tests: the `nth` operation (0-based, counted from arm()) of a kind fails.
namespace faults {
enum class Kind {
  kNoSpace,     // a write (fwrite or pwrite) fails with ENOSPC
  kReadError,   // a read (fread or pread) fails with EIO
  kShortRead,   // a read returns half of what it was asked, and every later read 0: the file ended there
  kRenameFails,  // a rename fails with EIO
  kMappedRead    // a copy out of a mapped file (copy_mapped) fails with EIO
};
void arm(Kind kind, uint64_t nth);
void disarm();
bool fired();          // whether the armed fault has happened
uint64_t operations();  // operations of the armed kind since arm()
}  // namespace faults

}  // namespace mv::io
