#include "file_ops.h"

#include <fcntl.h>
#include <setjmp.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <memory>
#include <mutex>
#include <utility>

#include "megavox/error.h"

namespace mv::io {

namespace faults {
namespace {
// Armed at most one at a time; atomics because readers and writers may run on worker threads.
std::atomic<bool> armed{false}, hit{false}, at_end{false};
std::atomic<Kind> kind{Kind::kNoSpace};
std::atomic<uint64_t> count{0}, target{0};

enum class Op { kRead, kWrite, kRename, kMappedRead };

Op op_of(Kind k) {
  switch (k) {
    case Kind::kNoSpace: return Op::kWrite;
    case Kind::kRenameFails: return Op::kRename;
    case Kind::kMappedRead: return Op::kMappedRead;
    default: return Op::kRead;
  }
}

// Whether this operation is the one to fail (counts operations of the armed kind's sort).
bool strikes(Op op) {
  if (!armed.load(std::memory_order_relaxed) || op_of(kind) != op) return false;
  return count.fetch_add(1) == target.load() && !hit.exchange(true);
}
}  // namespace

void arm(Kind k, uint64_t nth) {
  kind = k;
  target = nth;
  count = 0;
  hit = false;
  at_end = false;
  armed = true;
}
void disarm() {
  armed = false;
  at_end = false;
}
bool fired() { return hit; }
uint64_t operations() { return count; }
}  // namespace faults

namespace {
using faults::Kind;
using faults::Op;

// For a read: 0 = go on; else how to end it: -1 = fail with EIO, or 1 = a short read (half).
int read_fault() {
  if (faults::at_end) return 2;  // after a short read the file has ended
  if (!faults::strikes(Op::kRead)) return 0;
  if (faults::kind == Kind::kShortRead) {
    faults::at_end = true;
    return 1;
  }
  return -1;
}
}  // namespace

std::vector<uint8_t> read_at(std::FILE* f, uint64_t at, uint64_t n, const std::string& path) {
  std::vector<uint8_t> out(n);
  if (fseeko(f, static_cast<off_t>(at), SEEK_SET) != 0)
    throw Error(path + ": cannot seek to byte " + std::to_string(at) + ": " + std::strerror(errno));
  if (read_some(f, out.data(), n, path) != n) throw Error(path + ": the file ended early, at byte " + std::to_string(at));
  return out;
}

size_t read_some(std::FILE* f, void* data, size_t bytes, const std::string& path) {
  size_t want = bytes;
  switch (read_fault()) {
    case -1:
      throw IoError(path + ": read error: " + std::strerror(EIO));
    case 1:
      want = bytes / 2;
      break;
    case 2:
      return 0;
  }
  const size_t got = want ? std::fread(data, 1, want, f) : 0;
  if (got < want && std::ferror(f)) throw IoError(path + ": read error: " + std::strerror(errno));
  return got;
}

namespace memory_files {
namespace {
struct MemoryFile {
  std::string path;
  const void* bytes = nullptr;
  size_t size = 0;
} g_file;
}  // namespace

void put(const std::string& path, const void* bytes, size_t size) { g_file = {path, bytes, size}; }
void clear() { g_file = {}; }

// The memory file put for `path`, or nullptr.
const MemoryFile* find(const std::string& path) {
  return !g_file.path.empty() && g_file.path == path ? &g_file : nullptr;
}
}  // namespace memory_files

FilePtr open_read(const std::string& path) {
  if (const auto* m = memory_files::find(path)) {
    static char empty = 0;  // an empty input may come with no buffer
    FilePtr f(::fmemopen(m->size ? const_cast<void*>(m->bytes) : &empty, m->size, "rb"), &std::fclose);
    if (!f) throw IoError("cannot open '" + path + "' (a memory file): " + std::strerror(errno));
    return f;
  }
  FilePtr f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw IoError("cannot open '" + path + "': " + std::strerror(errno));
  return f;
}

FilePtr open_regular(const std::string& path, uint64_t* size) {
  FilePtr f = open_read(path);
  if (const auto* m = memory_files::find(path)) {
    *size = m->size;
  } else {
    struct stat st {};
    if (::fstat(::fileno(f.get()), &st) != 0) throw IoError(path + ": cannot read its size: " + std::strerror(errno));
    if (!S_ISREG(st.st_mode)) throw Error(path + ": not a regular file");
    *size = static_cast<uint64_t>(st.st_size);
  }
  std::setvbuf(f.get(), nullptr, _IONBF, 0);  // reads are large already; stdio's buffer would add a copy
  return f;
}

MappedFile::MappedFile(const std::string& path) {
  if (const auto* m = memory_files::find(path)) {
    data_ = static_cast<const unsigned char*>(m->bytes);
    size_ = m->size;
    return;
  }
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw IoError("cannot open '" + path + "': " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    const int e = errno;
    ::close(fd);
    throw IoError(path + ": cannot read its size: " + std::strerror(e));
  }
  size_ = static_cast<uint64_t>(st.st_size);
  if (size_ > 0) {
    void* p = ::mmap(nullptr, size_, PROT_READ, MAP_SHARED, fd, 0);
    const int e = errno;
    ::close(fd);  // the mapping keeps the file
    if (p == MAP_FAILED) throw IoError(path + ": cannot map: " + std::strerror(e));
    data_ = static_cast<const unsigned char*>(p);
    mapped_ = true;
  } else {
    ::close(fd);
  }
}

MappedFile::MappedFile(MappedFile&& other) noexcept
    : data_(std::exchange(other.data_, nullptr)), size_(std::exchange(other.size_, 0)),
      mapped_(std::exchange(other.mapped_, false)) {}

MappedFile& MappedFile::operator=(MappedFile&& other) noexcept {
  std::swap(data_, other.data_);  // what this held is unmapped with `other`
  std::swap(size_, other.size_);
  std::swap(mapped_, other.mapped_);
  return *this;
}

MappedFile::~MappedFile() {
  if (mapped_) ::munmap(const_cast<unsigned char*>(data_), size_);
}

std::string first_bytes(const std::string& path, size_t n) {
  FilePtr f = open_read(path);
  std::string head(n, '\0');
  head.resize(read_some(f.get(), head.data(), n, path));
  return head;
}

std::vector<char> read_whole_file(const std::string& path) {
  FilePtr f = open_read(path);
  std::vector<char> bytes;
  // the size is a hint only (a pipe has none); reading stops at the end of the data
  if (std::fseek(f.get(), 0, SEEK_END) == 0) {
    const long size = std::ftell(f.get());
    if (size > 0) bytes.reserve(static_cast<size_t>(size));
    std::fseek(f.get(), 0, SEEK_SET);
  }
  char chunk[1 << 16];
  while (size_t got = read_some(f.get(), chunk, sizeof chunk, path)) bytes.insert(bytes.end(), chunk, chunk + got);
  return bytes;
}

bool write_all(std::FILE* f, const void* data, size_t bytes) {
  if (faults::strikes(Op::kWrite)) {
    errno = ENOSPC;
    return false;
  }
  return bytes == 0 || std::fwrite(data, 1, bytes, f) == bytes;
}

ssize_t pread_some(int fd, void* data, size_t bytes, off_t offset) {
  switch (read_fault()) {
    case -1:
      errno = EIO;
      return -1;
    case 1:
      bytes /= 2;
      break;
    case 2:
      return 0;
  }
  return ::pread(fd, data, bytes, offset);
}

ssize_t pwrite_some(int fd, const void* data, size_t bytes, off_t offset) {
  if (faults::strikes(Op::kWrite)) {
    errno = ENOSPC;
    return -1;
  }
  return ::pwrite(fd, data, bytes, offset);
}

namespace {
// A mapped file that another process truncates raises SIGBUS on the pages past its new end. copy_mapped turns
// that into a failed copy: a handler, installed once, jumps back to the copy that set this thread's guard;
// a SIGBUS with no guard set goes to the disposition that was there before.
thread_local sigjmp_buf* t_copy_guard = nullptr;
struct sigaction g_previous_sigbus {};

void on_sigbus(int sig, siginfo_t* info, void* context) {
  if (sigjmp_buf* guard = t_copy_guard) siglongjmp(*guard, 1);
  if (g_previous_sigbus.sa_flags & SA_SIGINFO) {
    g_previous_sigbus.sa_sigaction(sig, info, context);
  } else if (g_previous_sigbus.sa_handler != SIG_DFL && g_previous_sigbus.sa_handler != SIG_IGN) {
    g_previous_sigbus.sa_handler(sig);
  } else {  // the default: die of SIGBUS, as without us
    ::signal(SIGBUS, SIG_DFL);
    ::raise(SIGBUS);
  }
}

void install_sigbus_guard() {
  static std::once_flag once;
  std::call_once(once, [] {
    struct sigaction sa {};
    sa.sa_sigaction = on_sigbus;
    sa.sa_flags = SA_SIGINFO | SA_NODEFER;
    sigemptyset(&sa.sa_mask);
    ::sigaction(SIGBUS, &sa, &g_previous_sigbus);
  });
}
}  // namespace

bool copy_mapped(void* out, const void* mapped, size_t bytes) {
  if (faults::strikes(Op::kMappedRead)) {
    errno = EIO;
    return false;
  }
  install_sigbus_guard();
  sigjmp_buf guard;
  if (sigsetjmp(guard, 1) != 0) {  // the mapping ended inside the range: the file shrank after it was mapped
    t_copy_guard = nullptr;
    errno = EFAULT;
    return false;
  }
  t_copy_guard = &guard;
  std::atomic_signal_fence(std::memory_order_seq_cst);  // the guard is set before the copy, cleared after it
  std::memcpy(out, mapped, bytes);
  std::atomic_signal_fence(std::memory_order_seq_cst);
  t_copy_guard = nullptr;
  return true;
}

int rename_path(const char* from, const char* to) {
  if (faults::strikes(Op::kRename)) {
    errno = EIO;
    return -1;
  }
  return std::rename(from, to);
}

int exchange_paths(const char* a, const char* b) {
  if (faults::strikes(Op::kRename)) {
    errno = EIO;
    return -1;
  }
  return ::renameat2(AT_FDCWD, a, AT_FDCWD, b, RENAME_EXCHANGE);
}

int link_open_file(int fd, const char* to) {
  if (faults::strikes(Op::kRename)) {
    errno = EIO;
    return -1;
  }
  // Through /proc, which needs no privilege; AT_EMPTY_PATH (CAP_DAC_READ_SEARCH) where /proc is not mounted.
  const std::string self = "/proc/self/fd/" + std::to_string(fd);
  if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, to, AT_SYMLINK_FOLLOW) == 0) return 0;
  if (errno != ENOENT) return -1;
  return ::linkat(fd, "", AT_FDCWD, to, AT_EMPTY_PATH);
}

}  // namespace mv::io
