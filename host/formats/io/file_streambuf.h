// A std::istream's buffer over megavox's file layer (io/file_ops.h), for the libraries that read from a
// std::istream (OpenVDB): their reads go through io::read_some, so the test seams -- injected read faults,
// memory files -- reach them too.
#pragma once
#include <memory>
#include <streambuf>
#include <string>

#include "io/file_ops.h"

namespace mv::io {

// Reads `path` (opened by io::open_read: mv::Error when it cannot be) in 64 KiB blocks; seeks within the block
// read last move in it. A read error throws mv::Error out of the stream's read (std::istream passes a buffer's
// exception on when its exceptions include badbit, else sets badbit).
class FileStreambuf final : public std::streambuf {
 public:
  explicit FileStreambuf(const std::string& path);

 protected:
  int_type underflow() override;
  pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) override;
  pos_type seekpos(pos_type pos, std::ios_base::openmode which) override;

 private:
  FilePtr file_;
  std::string path_;
  static constexpr size_t kBlock = size_t{1} << 16;
  std::unique_ptr<char[]> block_;  // not zeroed: only what was read is ever read
  off_type start_ = 0;  // the file offset of block_[0]; the file's own position is at the block's end
};

}  // namespace mv::io
