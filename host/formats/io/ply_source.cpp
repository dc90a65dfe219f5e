// The PLY reader's buffered input (ply_source.h), its cold parts: opening the file, refilling the buffer and
// reading header lines.
#include "ply_source.h"

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "file_ops.h"
#include "megavox/error.h"

namespace mv::io::detail {

Source::Source(const std::string& path) : path_(path), file_(open_regular(path, &size_)) {
  capacity_ = std::clamp<uint64_t>(size_, 4096, kBufferBytes);
  buffer_ = std::make_unique_for_overwrite<char[]>(capacity_);
  pos_ = end_ = buffer_.get();
}

bool Source::header_line(std::string& out, size_t max_chars) {
  out.clear();
  for (;;) {
    if (pos_ == end_ && !fill(1)) throw EndOfData{};
    char c = *pos_++;
    if (c == '\n') break;
    if (out.size() == max_chars) return false;
    out.push_back(c);
  }
  ++line_;
  if (!out.empty() && out.back() == '\r') out.pop_back();
  return true;
}

void Source::seek(uint64_t offset) {
  if (fseeko(file_.get(), static_cast<off_t>(offset), SEEK_SET) != 0)
    throw Error(path_ + ": cannot seek to byte " + num(offset) + ": " + std::strerror(errno));
  pos_ = end_ = buffer_.get();
  read_ = offset;
}

bool Source::fill(size_t n) {
  size_t have = static_cast<size_t>(end_ - pos_);
  std::memmove(buffer_.get(), pos_, have);
  pos_ = buffer_.get();
  end_ = pos_ + have;
  while (have < n) {
    size_t got = read_some(file_.get(), end_, capacity_ - have, path_);
    if (got == 0) return false;
    end_ += got;
    have += got;
    read_ += got;
  }
  return true;
}

}  // namespace mv::io::detail
