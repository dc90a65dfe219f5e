// The one door of megavox's own file code to the file system: every read, write and rename of a reader or
// writer goes through here, so tests can make one of them fail (io::faults below) without root-only tricks.
// In normal runs these are the plain stdio / POSIX calls. (Files that assimp and OpenVDB open themselves do
// not pass here; their outputs still go through our rename.)
#pragma once
#include <sys/types.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace mv::io {

// Up to `bytes` from `f`: fewer only at the end of the file. A read error throws mv::Error
// "PATH: read error: ...".
size_t read_some(std::FILE* f, void* data, size_t bytes, const std::string& path);
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
