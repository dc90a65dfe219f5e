// Human sizes: "512M" <-> bytes (binary units, as --device-memory and --n read them).
#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>

#include "megavox/device.h"
#include "megavox/error.h"

namespace mv {

uint64_t parse_size(std::string_view text) {
  std::string s(text);
  auto bad = [&]() {
    return CodedError(ErrorCode::invalid_argument, "'" + s + "' is not a size (examples: 1048576, 16K, 512M, 2G)");
  };
  if (s.empty() || !std::isdigit(static_cast<unsigned char>(s[0]))) throw bad();
  size_t pos = 0;
  uint64_t value = 0;
  while (pos < s.size() && std::isdigit(static_cast<unsigned char>(s[pos]))) {
    if (value > (UINT64_MAX - 9) / 10) throw bad();
    value = value * 10 + static_cast<uint64_t>(s[pos++] - '0');
  }
  std::string unit = s.substr(pos);
  if (unit.size() == 3 && unit.substr(1) == "iB") unit.resize(1);  // KiB, MiB, GiB, TiB
  if (unit.size() == 2 && (unit[1] == 'B' || unit[1] == 'b')) unit.resize(1);  // KB, MB, GB, TB (binary)
  int shift = 0;
  if (unit.empty()) shift = 0;
  else if (unit == "K" || unit == "k") shift = 10;
  else if (unit == "M" || unit == "m") shift = 20;
  else if (unit == "G" || unit == "g") shift = 30;
  else if (unit == "T" || unit == "t") shift = 40;
  else throw bad();
  if (shift && value > (UINT64_MAX >> shift)) throw bad();
  return value << shift;
}

std::string format_bytes(uint64_t bytes) {
  const char* units[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  double v = static_cast<double>(bytes);
  int u = 0;
  while (v >= 1024.0 && u < 4) {
    v /= 1024.0;
    ++u;
  }
  char buf[32];
  if (u == 0) std::snprintf(buf, sizeof buf, "%llu B", static_cast<unsigned long long>(bytes));
  else std::snprintf(buf, sizeof buf, "%.1f %s", v, units[u]);
  return buf;
}

}  // namespace mv
