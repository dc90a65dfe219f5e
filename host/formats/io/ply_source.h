// The PLY reader's buffered input: the file read in large blocks and handed out in small contiguous pieces
// (binary values, record windows, header lines, ascii tokens). The hot reads are inline; opening, refilling
// and header lines are in ply_source.cpp. Internal to host/io; not a public API.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <utility>

#include "file_ops.h"
#include "megavox/error.h"
#include "ply_header.h"

namespace mv::io::detail {

inline constexpr size_t kMaxToken = 64;  // longest ascii value ("-1.2345678901234567e-308" is 24)
inline constexpr size_t kBufferBytes = 1 << 20;

// Reads the file in large blocks and hands out small contiguous pieces of it.
class Source final : public HeaderLines {
 public:
  explicit Source(const std::string& path);
  const std::string& path() const override { return path_; }
  uint64_t size() const { return size_; }
  uint64_t consumed() const override { return read_ - static_cast<uint64_t>(end_ - pos_); }
  uint64_t line() const override { return line_; }  // ascii: the line being read, 1-based

  // The next n bytes, contiguous (n <= 8: one binary value).
  const char* take(size_t n) {
    if (static_cast<size_t>(end_ - pos_) < n && !fill(n)) throw EndOfData{};
    const char* p = pos_;
    pos_ += n;
    return p;
  }

  // The buffered bytes from the read position, after trying to make at least n available (fewer at the end
  // of the file). For decoding many binary records at once; advance() moves past what was used.
  std::pair<const char*, const char*> window(size_t n) {
    if (static_cast<size_t>(end_ - pos_) < n) fill(n);
    return {pos_, end_};
  }
  void advance(size_t n) { pos_ += n; }
  // Reads on from byte `offset` of the file (the buffer is dropped).
  void seek(uint64_t offset);

  void skip(uint64_t n) {
    while (n > 0) {
      if (pos_ == end_ && !fill(1)) throw EndOfData{};
      size_t k = static_cast<size_t>(std::min<uint64_t>(n, static_cast<uint64_t>(end_ - pos_)));
      pos_ += k;
      n -= k;
    }
  }

  // One header line without "\n" or "\r\n". False if it is longer than max_chars.
  bool header_line(std::string& out, size_t max_chars) override;

  // The next whitespace-separated ascii token; valid until the next call. Inline: called per ascii value.
  std::string_view token() {
    for (;; ++pos_) {
      if (pos_ == end_ && !fill(1)) throw EndOfData{};
      if (*pos_ == '\n') ++line_;
      else if (!is_space(*pos_)) break;
    }
    size_t n = 1;
    while ((pos_ + n < end_ || fill(n + 1)) && !is_space(pos_[n]) && pos_[n] != '\n')
      if (++n > kMaxToken) throw Error(path_ + ": line " + num(line_) + ": value longer than " + num(kMaxToken) + " characters");
    std::string_view t(pos_, n);
    pos_ += n;
    return t;
  }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r'; }

  // Makes at least n bytes available after pos_ (moving the rest to the front); false if the file ends first.
  bool fill(size_t n);

  std::string path_;
  uint64_t size_ = 0;  // before file_: opening it sets the size
  FilePtr file_;
  size_t capacity_ = 0;
  std::unique_ptr<char[]> buffer_;
  char* pos_ = nullptr;
  char* end_ = nullptr;
  uint64_t read_ = 0;
  uint64_t line_ = 1;
};

}  // namespace mv::io::detail
