#include "mvm_file.h"

#include <xxhash.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include "atomic_file.h"
#include "megavox/error.h"

namespace mv::io {

namespace {

constexpr char kMagic[8] = {'M', 'V', 'M', 'A', 'S', 'K', '\r', '\n'};

template <class T>
void put(std::vector<uint8_t>& out, T v) {
  uint8_t b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));  // little-endian hosts only (as every megavox file)
  out.insert(out.end(), b, b + sizeof(T));
}

template <class T>
T get(std::span<const uint8_t> b, size_t at) {
  T v;
  std::memcpy(&v, b.data() + at, sizeof(T));
  return v;
}

}  // namespace

void write_mvm(const std::string& path, const MaskModel& m) {
  if ((m.channels != 1 && m.channels != 3) || m.fg.size() != m.bins() || m.bg.size() != m.bins())
    throw Error("write_mvm: the model's bins do not match its channels");
  std::vector<uint8_t> out(kMagic, kMagic + 8);
  put<uint32_t>(out, kMvmVersion);
  put<uint32_t>(out, m.channels);
  put<uint32_t>(out, m.bins());
  put<uint32_t>(out, 0);
  for (uint64_t v : m.fg) put(out, v);
  for (uint64_t v : m.bg) put(out, v);
  put<uint64_t>(out, XXH64(out.data(), out.size(), 0));
  write_atomically(path, [&](std::FILE* f) { return std::fwrite(out.data(), 1, out.size(), f) == out.size(); });
}

MaskModel decode_mvm(std::span<const uint8_t> b, const std::string& name) {
  auto fail = [&](const std::string& why) -> MaskModel { throw Error("mask model '" + name + "': " + why); };
  if (b.size() < 32 || std::memcmp(b.data(), kMagic, 8) != 0) return fail("not a .mvm file (no MVMASK header)");
  const uint32_t version = get<uint32_t>(b, 8), channels = get<uint32_t>(b, 12), bins = get<uint32_t>(b, 16);
  if (version != kMvmVersion)
    return fail("version " + std::to_string(version) + "; this megavox reads version " + std::to_string(kMvmVersion));
  if (channels != 1 && channels != 3) return fail(std::to_string(channels) + " channels (1 or 3 expected)");
  MaskModel m = MaskModel::empty(channels);
  if (bins != m.bins() || get<uint32_t>(b, 20) != 0)
    return fail(std::to_string(bins) + " bins where a " + std::to_string(channels) + "-channel model has " +
                std::to_string(m.bins()));
  const size_t expect = 24 + 16 * size_t{bins} + 8;
  if (b.size() != expect)
    return fail(std::to_string(b.size()) + " bytes where the header says " + std::to_string(expect) +
                (b.size() < expect ? " (truncated)" : ""));
  if (XXH64(b.data(), expect - 8, 0) != get<uint64_t>(b, expect - 8)) return fail("checksum mismatch (damaged file)");
  uint64_t total = 0;
  for (uint32_t k = 0; k < bins; ++k) {
    m.fg[k] = get<uint64_t>(b, 24 + 8 * size_t{k});
    m.bg[k] = get<uint64_t>(b, 24 + 8 * (size_t{bins} + k));
    if (m.fg[k] > (uint64_t{1} << 52) || m.bg[k] > (uint64_t{1} << 52)) return fail("a bin count is over 2^52");
    total += m.fg[k] + m.bg[k];
  }
  if (total == 0) return fail("no training pixels");
  return m;
}

MaskModel read_mvm(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot open mask model '" + path + "': " + std::strerror(errno));
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return decode_mvm(bytes, path);
}

}  // namespace mv::io
