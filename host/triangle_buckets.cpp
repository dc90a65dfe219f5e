#include "triangle_buckets.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include "megavox/error.h"

namespace mv {

namespace {

std::string spill_dir() {
  const char* dir = std::getenv("TMPDIR");
  return dir && *dir ? dir : "/tmp";
}

}  // namespace

TriangleBuckets::TriangleBuckets(uint32_t per_axis, uint32_t cube, uint64_t budget)
    : per_axis_(per_axis), cube_(cube), budget_(budget) {
  const size_t n = size_t{per_axis} * per_axis * per_axis;
  mem_.resize(n);
  file_.resize(n);
}

TriangleBuckets::~TriangleBuckets() {
  if (fd_ >= 0) ::close(fd_);
}

void TriangleBuckets::add(const std::vector<float>& tris) {
  for (size_t t = 0; t + 9 <= tris.size(); t += 9) {
    uint32_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      const double mn = std::min({double(tris[t + a]), double(tris[t + 3 + a]), double(tris[t + 6 + a])});
      const double mx = std::max({double(tris[t + a]), double(tris[t + 3 + a]), double(tris[t + 6 + a])});
      lo[a] = std::min<uint32_t>(per_axis_ - 1, static_cast<uint32_t>(std::max(0.0, std::floor(mn)) / cube_));
      hi[a] = std::min<uint32_t>(per_axis_ - 1, static_cast<uint32_t>(std::max(0.0, std::floor(mx)) / cube_));
    }
    for (uint32_t x = lo[0]; x <= hi[0]; ++x)
      for (uint32_t y = lo[1]; y <= hi[1]; ++y)
        for (uint32_t z = lo[2]; z <= hi[2]; ++z) {
          std::vector<float>& b = mem_[bucket(x, y, z)];
          b.insert(b.end(), tris.begin() + t, tris.begin() + t + 9);
          held_ += 9 * sizeof(float);
        }
    if (held_ > budget_) spill();
  }
}

void TriangleBuckets::spill() {
  if (fd_ < 0) {
    std::string path = spill_dir() + "/megavox-triangles-XXXXXX";
    fd_ = ::mkstemp(path.data());
    if (fd_ < 0)
      throw Error("spilling triangles to " + spill_dir() + " (over --memory): " + std::strerror(errno) +
                  "; set TMPDIR to a writable directory");
    ::unlink(path.c_str());  // the file lives until it is closed
  }
  for (size_t b = 0; b < mem_.size(); ++b) {
    std::vector<float>& v = mem_[b];
    if (v.empty()) continue;
    const uint64_t bytes = v.size() * sizeof(float);
    const char* p = reinterpret_cast<const char*>(v.data());
    for (uint64_t done = 0; done < bytes;) {
      const ssize_t w = ::pwrite(fd_, p + done, bytes - done, static_cast<off_t>(file_bytes_ + done));
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0)
        throw Error("spilling triangles to " + spill_dir() + ": " + (w < 0 ? std::strerror(errno) : "disk full"));
      done += static_cast<uint64_t>(w);
    }
    file_[b].push_back({file_bytes_, v.size()});
    file_bytes_ += bytes;
    std::vector<float>().swap(v);  // give the memory back
  }
  held_ = 0;
}

std::vector<float> TriangleBuckets::take(uint32_t x, uint32_t y, uint32_t z) {
  const size_t b = bucket(x, y, z);
  std::vector<float> out;
  uint64_t floats = mem_[b].size();
  for (const Chunk& c : file_[b]) floats += c.floats;
  out.reserve(floats);
  for (const Chunk& c : file_[b]) {
    const size_t at = out.size();
    out.resize(at + c.floats);
    char* p = reinterpret_cast<char*>(out.data() + at);
    const uint64_t bytes = c.floats * sizeof(float);
    for (uint64_t done = 0; done < bytes;) {
      const ssize_t r = ::pread(fd_, p + done, bytes - done, static_cast<off_t>(c.offset + done));
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0) throw Error("reading spilled triangles back: " + std::string(r < 0 ? std::strerror(errno) : "short read"));
      done += static_cast<uint64_t>(r);
    }
  }
  out.insert(out.end(), mem_[b].begin(), mem_[b].end());
  held_ -= mem_[b].size() * sizeof(float);
  std::vector<float>().swap(mem_[b]);
  std::vector<Chunk>().swap(file_[b]);
  return out;
}

}  // namespace mv
