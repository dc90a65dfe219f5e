#include "plain_read.h"

#include <cstdio>
#include <vector>

#include "megavox/error.h"
#include "stopwatch.h"

namespace mv::bench {

PlainRead plain_read(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw Error(path + ": cannot be read");
  std::vector<char> buf(1 << 20);
  PlainRead r;
  auto t = Clock::now();
  for (size_t got; (got = std::fread(buf.data(), 1, buf.size(), f)) > 0;) r.bytes += got;
  r.seconds = since(t);
  const bool failed = std::ferror(f);
  std::fclose(f);
  if (failed) throw Error(path + ": read error");
  return r;
}

}  // namespace mv::bench
