// On-disk cache of compiled kernels (see kernel_cache.h).
#include "kernel_cache.h"

#include <unistd.h>
#include <xxhash.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

namespace mv::rt {

namespace fs = std::filesystem;

KernelCache::KernelCache(std::string dir) : dir_(dir.empty() ? default_dir() : std::move(dir)) {}

std::string KernelCache::default_dir() {
  auto env = [](const char* name) -> std::string {
    const char* v = std::getenv(name);
    return v ? v : "";
  };
  if (std::string d = env("MEGAVOX_KERNEL_CACHE"); !d.empty()) return d;
  if (std::string d = env("XDG_CACHE_HOME"); !d.empty()) return d + "/megavox/kernels";
  if (std::string d = env("HOME"); !d.empty()) return d + "/.cache/megavox/kernels";
  return {};
}

std::string KernelCache::key(std::initializer_list<std::string_view> parts) {
  XXH3_state_t* state = XXH3_createState();
  XXH3_128bits_reset(state);
  for (std::string_view p : parts) {
    const uint64_t size = p.size();  // lengths keep ("ab","c") apart from ("a","bc")
    XXH3_128bits_update(state, &size, sizeof size);
    XXH3_128bits_update(state, p.data(), p.size());
  }
  const XXH128_hash_t h = XXH3_128bits_digest(state);
  XXH3_freeState(state);
  char name[40];
  std::snprintf(name, sizeof name, "%016llx%016llx", static_cast<unsigned long long>(h.high64),
                static_cast<unsigned long long>(h.low64));
  return name;
}

bool KernelCache::contains(const std::string& key) const {
  std::error_code ec;
  return !dir_.empty() && fs::file_size(dir_ + "/" + key + ".bin", ec) > 0 && !ec;
}

std::optional<std::string> KernelCache::load(const std::string& key) const {
  if (dir_.empty()) return std::nullopt;
  std::ifstream in(dir_ + "/" + key + ".bin", std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (!in.good() && !in.eof()) return std::nullopt;
  std::string s = std::move(bytes).str();
  if (s.empty()) return std::nullopt;
  return s;
}

void KernelCache::store(const std::string& key, std::string_view bytes) const {
  if (dir_.empty() || bytes.empty()) return;
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec) return;
  const std::string path = dir_ + "/" + key + ".bin";
  static std::atomic<uint64_t> stores{0};  // devices of one process may store at once
  const std::string tmp = path + "." + std::to_string(getpid()) + "." + std::to_string(++stores) + ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      fs::remove(tmp, ec);
      return;
    }
  }
  fs::rename(tmp, path, ec);
  if (ec) fs::remove(tmp, ec);
}

}  // namespace mv::rt
