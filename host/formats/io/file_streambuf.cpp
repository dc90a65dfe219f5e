#include "io/file_streambuf.h"

#include <cstdio>

namespace mv::io {

FileStreambuf::FileStreambuf(const std::string& path)
    : file_(open_read(path)), path_(path), block_(new char[kBlock]) {
  setg(block_.get(), block_.get(), block_.get());
}

FileStreambuf::int_type FileStreambuf::underflow() {
  if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
  start_ += egptr() - eback();
  const size_t got = read_some(file_.get(), block_.get(), kBlock, path_);
  setg(block_.get(), block_.get(), block_.get() + got);
  return got ? traits_type::to_int_type(*gptr()) : traits_type::eof();
}

FileStreambuf::pos_type FileStreambuf::seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) {
  if (dir == std::ios_base::beg) return seekpos(off, which);
  if (dir == std::ios_base::cur) return seekpos(start_ + (gptr() - eback()) + off, which);
  if (std::fseek(file_.get(), 0, SEEK_END) != 0) return pos_type(off_type(-1));
  const long end = std::ftell(file_.get());
  start_ = end;  // the file's position and the (now empty) block's end agree again
  setg(block_.get(), block_.get(), block_.get());
  return end < 0 ? pos_type(off_type(-1)) : seekpos(end + off, which);
}

FileStreambuf::pos_type FileStreambuf::seekpos(pos_type pos, std::ios_base::openmode which) {
  const off_type to = pos;
  if (!(which & std::ios_base::in) || to < 0) return pos_type(off_type(-1));
  if (to >= start_ && to <= start_ + (egptr() - eback())) {  // inside the block: no system call
    setg(eback(), eback() + (to - start_), egptr());
    return pos;
  }
  if (std::fseek(file_.get(), static_cast<long>(to), SEEK_SET) != 0) return pos_type(off_type(-1));
  start_ = to;
  setg(block_.get(), block_.get(), block_.get());
  return pos;
}

}  // namespace mv::io
